// Reference (b): the white furnace, per pixel (docs/accuracy.md, "White furnace").
//
// A medium that scatters without absorbing (albedo 1, phase shading) inside a constant
// background of radiance L, no other light, multiple scattering with max_bounces far beyond
// any path length that occurs: radiance is L in every direction at every point, so every
// pixel's expected value is exactly L, for any optical thickness and any HG asymmetry g.
// Here: optical thickness tau = sigma_t * edge of the unit box in {0.01, 1, 10, 100},
// g in {-0.7, 0, 0.7}. (tau = 100 is affordable: a collision happens just inside the face, and
// most walks leave through the same face after a few hundred events; the benchmark
// bench/accuracy repeats it with 16 x more samples.)
//
// Test: per-pixel z against L with the film's sample variance, chi-square over pixels and
// Bonferroni max |z| at alpha = 1e-4; image mean |z| < 4 (two-sided 6.3e-5).
#include <catch2/catch.hpp>

#include "accuracy_support.h"
#include "reference_scenes.h"

using namespace tessera_acc;

namespace {

constexpr double kL = 0.6;

tessera::SceneDesc furnace(double tau, double g, int size, int spp) {
  tessera::SceneDesc s = furnace_scene(tau, g, kL);
  s.image = {size, size, spp, 0.0};
  s.options.seed = 7;
  return s;
}

void check(double tau, double g, int size, int spp, double alpha = 1e-4) {
  const std::vector<float> field = constant_field(5, 5, 5, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 5, 5, 5);
  const tessera::SceneDesc s = furnace(tau, g, size, spp);
  tessera::RenderStats st;
  const tessera::Film film = render(view, s, &st);
  const std::vector<double> expected(static_cast<std::size_t>(size) * size, kL);
  const PixelTest t = compare_to_expected(film, expected, nullptr, alpha);
  const ImageMean m = image_mean(film);
  INFO("tau " << tau << ", g " << g << ": " << t.describe() << "; image mean " << m.mean << " +- " << m.se
              << ", real collisions per sample " << static_cast<double>(st.real_collisions) / st.samples);
  CHECK(st.real_collisions > 0);
  CHECK(st.discarded_samples == 0);
  CHECK(t.ok());
  CHECK(m.z(kL) < 4.0);
}

}  // namespace

TEST_CASE("white furnace per pixel: tau 0.01, 1, 10, 100 and g -0.7, 0, 0.7", "[accuracy][furnace]") {
  for (const double tau : {0.01, 1.0, 10.0, 100.0}) {
    for (const double g : {-0.7, 0.0, 0.7}) {
      SECTION("tau " + std::to_string(tau) + ", g " + std::to_string(g)) {
        check(tau, g, 8, tau < 5.0 ? 1024 : tau < 50.0 ? 512 : 256);
      }
    }
  }
}
