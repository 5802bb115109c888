#pragma once
/// Writes the global temperature field to a raw file: float32, little-endian, i fastest, no
/// header, global_dims vertices (what `tessera-render` reads with `dtype: float32`). Every rank
/// writes its owned block with one collective MPI-IO call (a subarray file view), so the file
/// is the same for any number of ranks. The ranks write `<path>.tmp.<pid of rank 0>`, check every
/// result (error, written count, close; then rank 0 the file size) and agree; rank 0 then renames it onto `path`,
/// so a full disk or a file-size limit never leaves a truncated dump under `path` (an older one
/// stays). Collective; throws std::runtime_error naming the file and the fault on failure (on
/// every rank; a rank whose own write succeeded says "failed on another rank"). A device
/// solver's field is copied to the host for it (HeatSimulation::owned_values).
#include "cart_decomposition.h"
#include "heat_simulation.h"

#include <string>

namespace heat {

void dump_field(const CartDecomposition& decomp, const HeatSimulation& solver, const std::string& path);

}  // namespace heat
