#pragma once
/// HeatSolver: the heat equation dT/dt = alpha * laplacian(T) + q(x, t) on the unit cube,
/// explicit finite differences on a vertex-centred grid, in double precision.
///
/// Grid: N_a vertices along axis a at x_a = i * h_a, h_a = 1 / (N_a - 1), so vertices 0 and
/// N_a - 1 lie on the walls. Wall vertices keep the Dirichlet value `boundary_value`.
///
/// Scheme (forward Euler in time, second-order 7-point Laplacian in space), for every interior
/// vertex:
///   T' = T + dt * (alpha * sum_a (T[i-1_a] - 2 T + T[i+1_a]) / h_a^2 + q(x, t)).
/// It is stable for dt <= 1 / (2 alpha sum_a 1/h_a^2) (= h^2 / (6 alpha) on a cubic grid);
/// stable_dt() returns `safety` (0.9) times that limit. Every vertex's update reads only its
/// neighbours and its global position, so results are bit-identical for any decomposition.
///
/// Memory: each rank holds its owned block plus one ghost layer per side (also at the walls,
/// where the ghosts are unused), C order with i fastest; see HaloExchange. CudaHeatSolver
/// (heat_solver_cuda.h) is the same solver on a GPU; both are a HeatSimulation.
#include "cart_decomposition.h"
#include "halo_exchange.h"
#include "heat_simulation.h"
#include "heat_sources.h"

#include <functional>
#include <vector>

namespace heat {

struct HeatParams {
  double alpha = 0.01;            ///< diffusivity, domain units^2 / s
  double boundary_value = 300.0;  ///< wall temperature, K
  double initial_value = 300.0;   ///< interior temperature at t = 0, K
  double safety = 0.9;            ///< stable_dt() = safety * stability limit, in (0, 1]
  std::vector<HeatSource> sources;
};

/// The setup both solvers share: checks `params` against the grid (std::invalid_argument if an
/// axis has fewer than 3 vertices or a parameter is out of range) and returns the spacing h.
std::array<double, 3> checked_spacing(const CartDecomposition& decomp, const HeatParams& params);
/// safety times the stability limit 1 / (2 alpha sum_a 1/h_a^2).
double stable_time_step(const std::array<double, 3>& h, const HeatParams& params);
/// Throws std::invalid_argument unless dt is in (0, stable_dt / safety], the stability limit.
void check_time_step(double dt, double stable_dt, double safety);
/// Source s's contribution to the step [t, t + dt] on decomp's owned block (see SourceStamp):
/// the interior vertices within 6 sigma of its centre at t; beyond, exp(-18) of its peak is
/// dropped.
SourceStamp source_stamp(const HeatSource& s, double t, double dt, const CartDecomposition& decomp,
                         const std::array<double, 3>& h);

class HeatSolver final : public HeatSimulation {
 public:
  /// Throws std::invalid_argument if an axis has fewer than 3 vertices or parameters are out
  /// of range. Collective (exchanges the initial halo).
  HeatSolver(const CartDecomposition& decomp, const HeatParams& params);

  /// Sets the interior to f(x, y, z) (walls stay at boundary_value). Collective.
  void set_initial(const std::function<double(double, double, double)>& f);

  double stable_dt() const override { return m_stable_dt; }
  /// Advances by dt (<= the stability limit; throws otherwise). Collective (halo exchange).
  void step(double dt) override;

  double time() const override { return m_time; }
  std::int64_t steps() const override { return m_steps; }
  const std::array<double, 3>& spacing() const override { return m_h; }

  /// The local array, ghosts included: array_dims() doubles, i fastest (host memory).
  const double* data() const override { return m_T.data(); }
  FieldMemory memory() const override { return FieldMemory::host; }
  const Index3& array_dims() const override { return m_dims; }
  /// Owned vertex (i, j, k), 0-based local indices.
  double at(std::int64_t i, std::int64_t j, std::int64_t k) const { return m_T[index(i, j, k)]; }

  /// Min and max over this rank's owned vertices.
  std::pair<double, double> local_range() const override;
  std::vector<double> owned_values() const override;

 private:
  std::size_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(((k + 1) * m_dims[1] + (j + 1)) * m_dims[0] + (i + 1));
  }
  void apply_walls(std::vector<double>& field) const;
  void add_sources(double dt);

  const CartDecomposition& m_decomp;
  HeatParams m_params;
  HaloExchange m_halo;
  Index3 m_dims{};  ///< local array extent, ghosts included
  std::array<double, 3> m_h{};
  double m_stable_dt = 0.0;
  double m_time = 0.0;
  std::int64_t m_steps = 0;
  std::vector<double> m_T, m_next;
};

}  // namespace heat
