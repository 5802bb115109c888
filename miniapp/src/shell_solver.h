#pragma once
/// ShellSolver: the heat equation dT/dt = alpha * laplacian(T) + q(x, t) on a cylindrical
/// shell (ShellGeometry), explicit finite volumes on the shell's vertex grid, periodic in the
/// angle, the columns of angles split over the ranks (RingDecomposition).
///
/// Walls (Dirichlet): the floor and ceiling (z = 0, height) hold `wall_value`, the inner and
/// outer cylinders `inner_value` and `outer_value` (the cylinders win where they meet the
/// floor and ceiling). For every other vertex, with r_{i+-1/2} = r_i +- dr / 2:
///   T' = T + dt * (alpha * L[T] + q(x, t)),
///   L[T] = (r_{i+1/2} (T_{i+1} - T) - r_{i-1/2} (T - T_{i-1})) / (r_i dr^2)
///        + (T_{j+1} - 2 T + T_{j-1}) / (r_i dtheta)^2 + (T_{k+1} - 2 T + T_{k-1}) / dz^2,
/// the conservative (flux) form of the Laplacian in cylindrical coordinates, second order.
/// Stable for dt <= 1 / (2 alpha (1/dr^2 + 1/(r_1 dtheta)^2 + 1/dz^2)), r_1 = r0 + dr the
/// smallest radius updated; stable_dt() is `safety` times that. Every vertex's update reads
/// its six neighbours and its global position only: bit-identical for any number of ranks.
///
/// Memory: each rank holds its owned columns plus one ghost column per side, column after
/// column; in a column r after r, in each radius z fastest: vertex (i, k) of local column j
/// (-1 .. owned) at ((j + 1) n_r + i) n_z + k.
#include "heat_sources.h"
#include "ring_decomposition.h"
#include "shell_geometry.h"

#include <functional>
#include <utility>
#include <vector>

namespace heat {

struct ShellParams {
  ShellGeometry geometry;
  double alpha = 0.01;         ///< diffusivity, length^2 / s
  double wall_value = 300.0;   ///< floor and ceiling, K
  double inner_value = 300.0;  ///< inner cylinder r = r0, K
  double outer_value = 300.0;  ///< outer cylinder r = r1, K
  double initial_value = 300.0;
  double safety = 0.9;  ///< in (0, 1]
  std::vector<HeatSource> sources;
};

/// The demo's parameters (tessera-heat-shell) on `geometry`: a warm inner cylinder (330 K,
/// the other walls 300 K) and two Gaussian sources (sigma 0.08) circling the axis at
/// mid-shell radius in opposite directions, at heights 0.65 and 0.35 of the shell, their
/// strength pulsing.
ShellParams shell_demo_params(const ShellGeometry& geometry);

class ShellSolver {
 public:
  /// Throws std::invalid_argument for a bad geometry or parameters, or fewer columns than
  /// ranks. Collective (exchanges the initial ghosts).
  ShellSolver(const RingDecomposition& ring, const ShellParams& params);

  /// Sets every vertex that is not on a wall to f(r, theta, z). Collective.
  void set_initial(const std::function<double(double, double, double)>& f);

  double stable_dt() const { return m_stable_dt; }
  /// Advances by dt (<= the stability limit; throws otherwise). Collective.
  void step(double dt);

  double time() const { return m_time; }
  const ShellParams& params() const { return m_params; }
  const ShellGeometry& geometry() const { return m_params.geometry; }

  /// The local array, ghost columns included: (owned + 2) n_r n_z doubles.
  const double* data() const { return m_T.data(); }
  std::int64_t column_size() const { return m_column; }
  /// Vertex (i, k) of local column j (-1 .. owned()).
  double at(std::int64_t i, std::int64_t j, std::int64_t k) const { return m_T[index(i, j, k)]; }

  /// Min and max over this rank's owned vertices.
  std::pair<double, double> local_range() const;

 private:
  std::size_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>((j + 1) * m_column + i * m_params.geometry.n_z + k);
  }
  void apply_walls(std::vector<double>& field) const;

  const RingDecomposition& m_ring;
  ShellParams m_params;
  std::int64_t m_column = 0;  ///< doubles per column, n_r n_z
  double m_stable_dt = 0.0;
  double m_time = 0.0;
  std::vector<double> m_T, m_next;
};

}  // namespace heat
