#pragma once
/// ShellGeometry: the cylindrical shell of tessera-heat-shell (docs/miniapp.md, "A curvilinear
/// mesh: the cylindrical shell"), r in [r0, r1], theta in [0, 2 pi), z in [0, height], and
/// its vertices on a logical grid.
///
/// Vertices: n_r radii r_i = r0 + i (r1 - r0) / (n_r - 1), n_theta angles theta_j =
/// 2 pi j / n_theta (periodic: column n_theta is column 0 again) and n_z heights z_k =
/// k height / (n_z - 1), at (r cos theta, r sin theta, z). A vertex's position depends on its
/// global (i, j mod n_theta, k) alone, so every rank computes the same bits for it, and the
/// seam's repeated column has exactly column 0's coordinates.
///
/// Logical axes as published (tessera_mesh_domain dims): z fastest, then r, then theta, the
/// solver's memory order (shell_solver.h). (z, r, theta) is a right-handed frame
/// (e_z x e_r = e_theta), so every cell is positively oriented.
#include <array>
#include <cstdint>
#include <vector>

namespace heat {

struct ShellGeometry {
  double r0 = 0.5;            ///< inner radius, > 0
  double r1 = 1.0;            ///< outer radius, > r0
  double height = 1.0;        ///< > 0
  std::int64_t n_r = 24;      ///< vertices along the radius
  std::int64_t n_theta = 96;  ///< columns of angles (periodic)
  std::int64_t n_z = 32;      ///< vertices along the height

  /// Throws std::invalid_argument unless n_r, n_z >= 3, n_theta >= 3 and the radii and
  /// height are in range.
  void validate() const;

  double dr() const { return (r1 - r0) / static_cast<double>(n_r - 1); }
  double dz() const { return height / static_cast<double>(n_z - 1); }
  double dtheta() const;
  double radius(std::int64_t i) const { return r0 + static_cast<double>(i) * dr(); }
  double theta(std::int64_t j) const;  ///< of column j mod n_theta (any integer j)
  double z(std::int64_t k) const { return static_cast<double>(k) * dz(); }
  std::array<double, 3> position(std::int64_t i, std::int64_t j, std::int64_t k) const;
};

/// The vertices of global columns first .. first + count - 1 (column indices taken mod
/// n_theta), in the published order (k fastest, then i, then the column): x, y and z each
/// n_z n_r count doubles.
struct ShellCoordinates {
  std::vector<double> x, y, z;
};
ShellCoordinates shell_block_coordinates(const ShellGeometry& g, std::int64_t first, std::int64_t count);

}  // namespace heat
