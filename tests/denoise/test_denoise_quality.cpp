// Does denoising help? An 8-spp render, denoised with Open Image Denoise, must be closer
// (RMSE over linear RGB) to an independent 1024-spp reference of the same scene (another
// seed) than the raw 8-spp estimate is. Exits 77 (CTest SKIP_RETURN_CODE) when OIDN cannot be
// found (denoiser.h: TESSERA_OIDN_LIBRARY, libOpenImageDenoise.so.2, pyoidn of python3 on
// PATH), 0 on success, 1 on failure. Also checks that denoising leaves RGBA untouched and
// runs on the threads asked for.
#include <tessera/denoiser.h>
#include <tessera/film.h>
#include <tessera/render.h>

#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

namespace {

using tessera::Color;
using tessera::Vec3;

constexpr int N = 40;  // field vertices per axis

/// Smooth blobs with sharp-ish iso-surfaces: surface-like shading from the gradient, where a
/// 8-spp estimate is grainy and the albedo/normal guide the denoiser.
std::vector<float> blob_field() {
  std::vector<float> f(static_cast<std::size_t>(N) * N * N);
  const Vec3 c1(0.35, 0.4, 0.45), c2(0.65, 0.6, 0.55);
  for (int k = 0; k < N; ++k)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        const Vec3 p(i / (N - 1.0), j / (N - 1.0), k / (N - 1.0));
        const double v = std::exp(-glm::dot(p - c1, p - c1) / 0.03) + 0.8 * std::exp(-glm::dot(p - c2, p - c2) / 0.02);
        f[(static_cast<std::size_t>(k) * N + j) * N + i] = static_cast<float>(v);
      }
  return f;
}

tessera::SceneDesc scene(int spp, std::uint64_t seed) {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(0.0);
  s.geometry.spacing = Vec3(1.0 / (N - 1));
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 40.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.3, 0.5, 1.0}, {0.0, 0.0, 1.0, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.5, 0.2), Color(0.2, 0.6, 0.9)});
  s.camera.position = Vec3(1.9, -1.2, 1.4);
  s.camera.look_at = Vec3(0.5);
  s.camera.fov_deg = 35.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, -1.0, 2.0), Vec3(0.5), 0.8, 0.8, Color(12.0)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.15, 0.15, 0.2);
  s.integrator.scattering = tessera::Scattering::Single;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 4.0;
  s.image = {96, 96, spp, 0.0};
  s.image.denoise = true;
  s.options.seed = seed;
  return s;
}

tessera::Image render(const tessera::FieldView& view, int spp, std::uint64_t seed) {
  const tessera::SceneDesc s = scene(spp, seed);
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::Film film(s.image.width, s.image.height, true);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  return film.resolve(false, false);
}

/// RMSE over the RGB of every pixel; `rgb` interleaved with `stride` floats per pixel.
double rmse(const float* rgb, int stride, const tessera::Image& ref) {
  const std::size_t n = static_cast<std::size_t>(ref.width) * ref.height;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(rgb[i * stride + c]) - ref.rgba[4 * i + c];
      sum += d * d;
    }
  return std::sqrt(sum / (3.0 * static_cast<double>(n)));
}

}  // namespace

int main() {
  try {
    try {
      std::printf("Open Image Denoise: %s\n", tessera::require_denoiser().c_str());
    } catch (const tessera::DenoiserUnavailable& e) {
      std::printf("SKIPPED: %s\n", e.what());
      return 77;
    }
    if (tessera::denoiser_threads() != 0) {
      std::printf("FAILED: denoiser_threads() is %d before any denoise\n", tessera::denoiser_threads());
      return 1;
    }
    const std::vector<float> field = blob_field();
    const tessera::FieldView view = tessera::FieldView::contiguous(field.data(), tessera::DType::Float32, N, N, N);
    const tessera::Image ref = render(view, 1024, 7);
    tessera::Image noisy = render(view, 8, 1);
    const std::vector<float> rgba = noisy.rgba;
    const auto t0 = std::chrono::steady_clock::now();
    tessera::denoise(noisy);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double raw = rmse(noisy.rgba.data(), 4, ref), den = rmse(noisy.denoised.data(), 3, ref);
    std::printf("96x96: RMSE to the 1024-spp reference: raw 8 spp %.5f, denoised %.5f (%.1f%%); denoise %.3f s\n", raw,
                den, 100.0 * den / raw, secs);
    if (noisy.rgba != rgba) {
      std::printf("FAILED: denoise changed the RGBA estimate\n");
      return 1;
    }
    if (!(den < raw)) {
      std::printf("FAILED: the denoised image is not closer to the reference than the raw one\n");
      return 1;
    }
    // Threads: 0 took the caller's arena's width; a count asked for is the one OIDN runs on
    // (the device remade for it), as closely denoised
    const int all = tbb::this_task_arena::max_concurrency();
    if (tessera::denoiser_threads() != all) {
      std::printf("FAILED: threads 0 in an arena of %d: OIDN runs on %d\n", all, tessera::denoiser_threads());
      return 1;
    }
    for (const int threads : {1, 2, 1}) {
      if (threads > all) continue;
      tessera::Image again = noisy;
      tessera::denoise(again, threads);
      const double d = rmse(again.denoised.data(), 3, ref);
      std::printf("denoise on %d thread(s): OIDN reports %d, RMSE %.5f\n", threads, tessera::denoiser_threads(), d);
      if (tessera::denoiser_threads() != threads || !(d < raw)) {
        std::printf("FAILED: asked for %d thread(s)\n", threads);
        return 1;
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
}
