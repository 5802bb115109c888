#pragma once
/// The blocks a rank holds of the global field (one per domain), read in place, and the
/// fault of blocks that do not fit together (LayoutError). Shared by the binding, the layout
/// checks and the parallel contexts that assemble or distribute the blocks.
#include <tessera/field_view.h>

#include <cstdint>
#include <stdexcept>

namespace tessera::insitu {

/// Where this rank's real vertices sit in the global grid (see tessera_grid in tessera.h).
struct GlobalPlacement {
  std::int64_t global_dims[3];
  std::int64_t offset[3];
};

/// One block of the global field this rank holds: its real elements, read in place.
struct FieldBlock {
  FieldView view;                      ///< real elements in the simulation's memory (validated)
  std::int64_t offset[3] = {0, 0, 0};  ///< global index of view's element (0, 0, 0)
  /// The caller's domain index (tessera_execute_domains), or -1 for tessera_execute's single
  /// block (messages then say "rank r" instead of "rank r domain d").
  int domain = -1;
  /// Refinement level (amr.h); offset and view.dims count elements of this level. 0 for a
  /// single-level mesh.
  int level = 0;
  /// view.data is device memory left where the simulation keeps it (a distributed render on
  /// the GPU, device_phase.h): the host reads none of it in place, only through the copies
  /// that name it (cuda_field_summary_accumulate, cuda_copy_box_to_host) after the work queued
  /// on `cuda_stream` (the simulation's; null: the whole device).
  bool on_device = false;
  void* cuda_stream = nullptr;
};

/// The ranks' fields do not fit together: boxes of real vertices that overlap, leave a gap,
/// leave the global grid, or ranks that disagree on dtype or global_dims (or publish an
/// invalid view). A fault in the simulation's descriptors, reported as TESSERA_ERROR_DATA
/// like the other descriptor faults. Thrown alike on every rank (each sees every box).
class LayoutError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tessera::insitu
