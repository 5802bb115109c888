#pragma once
/// Writes the global temperature field to a raw file: float32, little-endian, i fastest, no
/// header, global_dims vertices (what `tessera-render` reads with `dtype: float32`). Every rank
/// writes its owned block with one collective MPI-IO call (a subarray file view), so the file
/// is the same for any number of ranks. Collective; throws std::runtime_error naming the file
/// and the MPI error on failure (on every rank).
#include "cart_decomposition.h"
#include "heat_solver.h"

#include <string>

namespace heat {

void dump_field(const CartDecomposition& decomp, const HeatSolver& solver, const std::string& path);

}  // namespace heat
