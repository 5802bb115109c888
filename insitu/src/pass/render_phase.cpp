// The render phase of a render (render_phase.h).
#include "pass/render_phase.h"

#include <tessera/denoiser.h>
#include <tessera/film.h>

namespace tessera::insitu {
namespace {

bool render_film(PhaseGate& gate, const PassContext& pass, const PreparedScene& prepared, Film& film,
                 RenderResult& result) {
  return gate.run(TESSERA_ERROR_RENDER, [&] {
    // With image.denoise every rank keeps the auxiliary sums: they travel with the pixels
    film = Film(pass.spec.image.width, pass.spec.image.height, pass.spec.image.denoise);
    RenderStats stats;
    const auto t0 = PassClock::now();
    try {
      pass.ctx.render(prepared, film, stats);
    } catch (const DeadlineExceeded& e) {
      film = Film();  // the partial image is never resolved nor written
      time_limit_passed(pass, e);
    }
    result.render_seconds += std::chrono::duration<double>(PassClock::now() - t0).count();
    result.stats.add_counters(stats);
    result.stats.wall_seconds += stats.wall_seconds;
    result.stats.threads = stats.threads;
  });
}

bool resolve_image(PhaseGate& gate, const PassContext& pass, const Film& film, Image& img, RenderResult& result) {
  return gate.run(TESSERA_ERROR_RENDER, [&] {
    if (!pass.root()) return;
    img = film.resolve(pass.spec.output.variance, pass.spec.output.samples);
    if (!pass.spec.image.denoise) return;
    const auto t0 = PassClock::now();
    denoise(img);  // on the pass' threads (the arena run_render made of tessera.threads)
    result.denoise_seconds += std::chrono::duration<double>(PassClock::now() - t0).count();
  });
}

}  // namespace

std::optional<Image> render_phase(PhaseGate& gate, const PassContext& pass, const PreparedScene& prepared,
                                  RenderResult& result) {
  Film film;
  if (!render_film(gate, pass, prepared, film, result)) return std::nullopt;
  Image img;
  if (!resolve_image(gate, pass, film, img, result)) return std::nullopt;
  return img;
}

}  // namespace tessera::insitu
