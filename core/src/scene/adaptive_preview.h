#pragma once
/// prepare's adaptive preview (adaptive_sampling.h): the scale that turns a block's pilot
/// sigma into a pixel's sample count.
namespace tessera {

struct KernelScene;
struct RenderOptions;
/// The preview's scale for a kernel scene (0 when adaptive sampling is off), on
/// options.threads threads within options.deadline (DeadlineExceeded past it).
double adaptive_preview_scale(const KernelScene& ks, const RenderOptions& options);

}  // namespace tessera
