// Adaptive sampling (image.target_error > 0, docs/physics.md section 11) against the same
// analytic references as the rest of the suite (docs/accuracy.md, "Adaptive sampling").
//
// KNOWN FAILURE, hidden from the default run (tag [.]): a pixel stops once the relative
// standard error of its mean, estimated from its own samples, is below the target. When the
// first min(spp, max(8, spp / 16)) samples happen to be equal (common: a camera ray either
// escapes or not) the estimated variance is 0 and the pixel stops at that value; more
// generally, stopping on the samples' own variance biases the mean (optional stopping).
// Measured with this file (seed-fixed): an emissive box seen with collision probability ~0.1
// per sample over a black background renders ~30% too dark, a thin absorber in front of a
// white background a few percent too bright; both far outside the statistical tolerance.
// Run with: tessera_accuracy_tests "[adaptive]". Unhide once adaptive sampling is unbiased
// (or bounded, and this test states the bound).
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

namespace {

struct Case {
  const char* name;
  double sigma;
  bool emissive;  ///< emission 1 over black (dark pixels) vs absorber over white background
};

void check(const Case& c, double target) {
  const std::vector<float> field = constant_field(3, 3, 3, 1.0f);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, 3, 3, 3);
  tessera::SceneDesc s = unit_box_scene(c.sigma, 0.0);
  s.geometry.spacing = Vec3(0.5);
  if (c.emissive) s.tf.emission = tessera::ColorTF::constant(Color(1.0));
  else s.background.color = Color(1.0);
  s.camera.position = Vec3(0.5, 0.5, -1.5);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 20.0;
  s.image = {32, 32, 64, target};
  s.options.seed = 1300;
  const std::vector<double> T = expected_image(s, 8, [&](const Ray& r) {
    return std::exp(-c.sigma * chord(r, Vec3(0.0), Vec3(1.0)));
  });
  std::vector<double> P(T.size());  // probability of a sample of value 1
  for (std::size_t i = 0; i < T.size(); ++i) P[i] = c.emissive ? 1.0 - T[i] : T[i];
  tessera::RenderStats st;
  const tessera::Film film = render(view, s, &st);
  // Image mean of the pixel means against the expectation (pixels are independent; each
  // pixel's variance is P (1 - P) / n for its own n).
  double diff = 0.0, var = 0.0, expected = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const tessera::PixelSums& p = film.pixels()[i];
    diff += p.r / p.n - P[i];
    var += P[i] * (1.0 - P[i]) / p.n;
    expected += P[i];
  }
  const double n = static_cast<double>(P.size());
  INFO(c.name << ", target_error " << target << ": " << static_cast<double>(st.samples) / n
              << " samples per pixel, image mean " << (expected + diff) / n << " vs expected "
              << expected / n << " (" << diff / std::sqrt(var) << " standard errors, relative "
              << diff / expected << ")");
  CHECK(std::fabs(diff) < 4.0 * std::sqrt(var));
}

}  // namespace

TEST_CASE("adaptive sampling keeps the expected image (known failure: biased)",
          "[accuracy][adaptive][.]") {
  const Case cases[] = {{"emissive box over black, collision probability ~0.1", 0.07, true},
                        {"thin absorber over white, transmittance ~0.86", 0.15, false}};
  for (const Case& c : cases) {
    SECTION(c.name) {
      check(c, 0.0);  // adaptive sampling off: the reference itself
      check(c, 0.1);
    }
  }
}
