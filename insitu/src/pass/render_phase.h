#pragma once
/// The render phase: the prepared scene's tiles rendered across the ranks into one film
/// (ParallelContext::render, under tessera.time_limit), then rank 0 resolves the film into an
/// image and, with image.denoise, denoises it (the PNG shows the denoised RGB, the EXR gains
/// denoised.R/G/B); a denoiser failure fails the render with TESSERA_ERROR_RENDER.
#include "pass/pass_context.h"

#include <tessera/adapter.h>
#include <tessera/image.h>
#include <tessera/render.h>

#include <optional>

namespace tessera::insitu {

/// The image (rank 0; empty on the other ranks). Adds the render's seconds, stats and
/// denoising seconds to `result`. Nothing when the ranks agreed on a failure (a passed time
/// limit included: the partial image is never resolved nor written).
std::optional<Image> render_phase(PhaseGate& gate, const PassContext& pass, const PreparedScene& prepared,
                                  RenderResult& result);

}  // namespace tessera::insitu
