#pragma once
/// The device phase of a render (docs/gpu.md): where it traces, from `tessera.device`, where
/// the field lives and what the GPU covers; then the field made readable there. On the GPU a
/// field in device (or managed) memory that one rank holds whole is read in place, with no
/// copy; one rank's blocks of which some are device memory are assembled on the device, its
/// host blocks copied there (FieldDevice::assemble_on_device); on several ranks the staging
/// waits for the plan (stage_deferred: a distributed render leaves device blocks where they
/// are). Every other case that holds device memory (a replica of several ranks' blocks,
/// refinement levels, a vector's magnitude, a render on the CPU) stages those blocks to the
/// host, within the memory limit, and counts the bytes.
#include "pass/bind_phase.h"
#include "pass/pass_context.h"

#include <optional>

namespace tessera::insitu {

/// Decides the render's device and stages what must be (field.device). A `device: cuda` that
/// cannot be honoured (no CUDA build, no device, the GPU disabled, a feature the GPU does not
/// cover) fails the render with TESSERA_ERROR_RENDER naming why; `auto` falls back to the CPU.
/// Under MPI the ranks agree on one device kind (a rank on the CPU keeps every rank there),
/// so the image does not depend on which rank renders a tile. Collective; false when the
/// ranks agreed on a failure (the gate's outcome holds it).
bool device_phase(PhaseGate& gate, const PassContext& pass, BoundField& field);

/// The staging device_phase deferred (FieldDevice::deferred) for a render that is not
/// distributed after all: the device blocks copied to the host as device_phase would have,
/// their bytes added to `result`. Collective (a gate) for a render on the GPU on several
/// ranks (whether this rank deferred or not), nothing otherwise; false when the ranks agreed
/// on a failure.
bool stage_deferred(PhaseGate& gate, const PassContext& pass, BoundField& field, RenderResult& result);

/// The device of a render over curvilinear or unstructured domains, `gpu_readable` when some
/// of this rank's arrays were device or managed memory: `auto` renders on the GPU then, `cuda`
/// always. The mesh's elements are checked and its tables built on the host (device arrays
/// were staged there, mesh_staging.h), and a GPU render copies the tables and arrays to the
/// device (counted in bytes_to_device). Agreed as device_phase agrees; collective; nothing
/// when the ranks agreed on a failure.
std::optional<config::DeviceSelection> mesh_device_phase(PhaseGate& gate, const PassContext& pass, bool gpu_readable);

/// The GPU-side parts of the render's options: device, stream and device memory limit.
void set_device_options(const PassContext& pass, const BoundField& field, RenderOptions& options);
void set_device_options(const PassContext& pass, const config::DeviceSelection& sel, RenderOptions& options);

}  // namespace tessera::insitu
