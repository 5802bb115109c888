// Annotations through the adapter: the PNG of the render and of its Cinema views gains the
// colour bar and the text of the call's step and time, inside the annotation boxes only; the
// EXR is the same as without annotations.
#include <tessera/annotate.h>
#include <tessera/config/annotations.h>
#include <tessera/config/build_scene.h>
#include <tessera/config/config.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include "insitu_test_support.h"
#include "read_png.h"

#include <algorithm>

using namespace tessera;
using namespace tessera::insitu::test;
using tessera::insitu::Adapter;
using tessera_test::read_png_rgba;

namespace {

/// Pixels of two same-sized pictures that differ: inside any of `boxes`, and outside all.
std::pair<long, long> differences(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int w, int h,
                                  const std::vector<PixelBox>& boxes) {
  long inside = 0, outside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * w + x) * 4;
      if (std::equal(&a[i], &a[i] + 4, &b[i])) continue;
      const bool in = std::any_of(boxes.begin(), boxes.end(), [&](const PixelBox& bx) { return bx.contains(x, y); });
      ++(in ? inside : outside);
    }
  return {inside, outside};
}

}  // namespace

TEST_CASE("the adapter annotates its PNGs (Cinema views too) and leaves the EXR as it was", "[insitu][annotate]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string common =
      "    transfer_function: {range: [0, 250], density_scale: 40, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n"
      "    output: {file: \"{name}_{step:04d}\", formats: [exr, png], cinema: {azimuth: [0], elevation: [10]}}\n";
  const std::string notes =
      "    annotations: {colorbar: true, text: \"{name} step {step} t = {time:.2f}\", title: Blob}\n";
  const std::string renders = render_yaml("plain", "{every: 1}", common, "density", 96, 1) +
                              render_yaml("noted", "{every: 1}", common + notes, "density", 96, 1);
  const std::string cfg = dir.write("a.yaml", config_yaml(out, renders));
  constexpr int n = 8;
  const std::vector<float> sim = to_float(blob_values(n));
  const tessera_field field = dense_field("density", sim.data(), n);
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  REQUIRE(adapter.execute(7, 0.25, unit_grid(n), {&field, 1}) == TESSERA_OK);

  // Where the annotations go: the config's own description at step 7, time 0.25
  const config::Config c = config::load_config(cfg);
  const config::RenderSpec& spec = c.renders[1];
  const TransferFunction tf = config::build_transfer_function(spec.transfer_function, {0.0, 250.0});
  const AnnotationDesc d = config::build_annotations(*spec.annotations, spec.name, spec.field, tf, 7, 0.25);
  CHECK(d.texts[1].text == "noted step 7 t = 0.25");
  const std::vector<PixelBox> boxes = layout_annotations(96, 96, d).boxes;
  REQUIRE(boxes.size() == 3u);

  for (const std::string& base : {std::string("/plain_0007"), std::string("/plain.cdb/plain_0007_phi_0_theta_10")}) {
    INFO(base);
    std::string noted = base;
    for (std::size_t p; (p = noted.find("plain")) != std::string::npos;) noted.replace(p, 5, "noted");
    CHECK(same_pixels(read_exr(out + base + ".exr"), read_exr(out + noted + ".exr")));
    int w = 0, h = 0;
    const auto a = read_png_rgba(out + base + ".png", w, h);
    const auto b = read_png_rgba(out + noted + ".png", w, h);
    const auto [inside, outside] = differences(a, b, w, h, boxes);
    CHECK(inside > 0);
    CHECK(outside == 0);
  }
}
