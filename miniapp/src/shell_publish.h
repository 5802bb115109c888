#pragma once
/// ShellBlock: what tessera-heat-shell publishes, one curvilinear domain per rank
/// (tessera_mesh_domain, interfaces.md 7.2): the cells between the rank's owned columns of
/// angles and the next column, a closed block. Its vertex columns are the owned ones and the
/// right neighbour's first column, whose values the solver's high ghost column already holds,
/// so the temperature is read in place (no copy). The last rank's block ends on the seam: its
/// last column repeats column 0's coordinates bit for bit (ShellGeometry). Real cells of two
/// ranks never overlap; the shared vertex columns are published by both.
#include "shell_geometry.h"
#include "shell_solver.h"

#include <tessera/tessera.h>

namespace heat {

class ShellBlock {
 public:
  /// The coordinates of the rank's vertex columns (computed once; the mesh does not move).
  ShellBlock(const ShellGeometry& geometry, std::int64_t first_column, std::int64_t owned_columns);

  /// The domain, vertex data `field_name` read from the solver's array at this step (its
  /// owned columns and high ghost column). Valid while the solver's array and this block live.
  const tessera_mesh_domain& domain(const ShellSolver& solver, const char* field_name);

 private:
  ShellGeometry m_geometry;
  std::int64_t m_columns = 0;  ///< vertex columns: owned + 1
  ShellCoordinates m_coords;
  tessera_field m_field{};
  tessera_mesh_domain m_domain{};
};

}  // namespace heat
