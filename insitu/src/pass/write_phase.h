#pragma once
/// The write phase (rank 0): the image's files in every output format, with the render's
/// annotations (title, step, time, colour bar) drawn into the PNG; the image kept as the
/// render's last. An I/O failure is TESSERA_ERROR_IO on every rank.
#include "pass/pass_context.h"

#include <tessera/adapter.h>
#include <tessera/annotate.h>
#include <tessera/image.h>
#include <tessera/scene.h>

#include <optional>
#include <string>

namespace tessera::insitu {

/// The render's annotations at this call's step and time (the colour bar of the scene's TF,
/// range resolved), or none.
std::optional<AnnotationDesc> annotations_of(const PassContext& pass, const SceneDesc& scene);

/// Writes `img` (rank 0; other ranks write nothing) to the render's output path for this
/// step, appends the files to result.files and keeps the image as render.last_image.
/// False when the ranks agreed on a failure.
bool write_phase(PhaseGate& gate, const PassContext& pass, const SceneDesc& scene, Image img, RenderResult& result);

}  // namespace tessera::insitu
