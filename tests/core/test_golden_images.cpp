// Golden images: a fixed set of small scenes, rendered by the code of the time they were made
// and stored in tests/data/golden, must render to the same bytes today. Together they take
// every branch of the estimator: both free-path modes (delta tracking, raymarch), both shadow
// estimators (ratio with and without roulette, delta), rect and sphere lights, constant,
// gradient and environment-map backgrounds (visible and hidden), emission, phase / BRDF /
// hybrid shading, single and multiple scattering, grid and global majorants, adaptive
// sampling, a thin lens, tile culling and every field dtype. A refactor of the kernels that
// changes any random-number use, any counter or any floating-point operation order fails here.
//
// To re-make the images after a change that is meant to alter them (never in a refactor):
//   TESSERA_UPDATE_GOLDEN=1 build/tests/tessera_tests "[golden]"
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "test_support.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int NX = 18, NY = 16, NZ = 14;
constexpr int W = 24, H = 16;

/// The blobby field in any dtype: [0, 1] scaled to the type's useful range.
struct Field {
  std::vector<float> f32;
  std::vector<double> f64;
  std::vector<std::uint8_t> u8;
  std::vector<std::uint16_t> u16;
  std::vector<std::int16_t> i16;
  Field() : f32(tessera_test::blobby_field(NX, NY, NZ)) {
    for (const float v : f32) {
      f64.push_back(static_cast<double>(v) * 0.5 + 0.25);
      u8.push_back(static_cast<std::uint8_t>(v * 255.0f));
      u16.push_back(static_cast<std::uint16_t>(v * 60000.0f));
      i16.push_back(static_cast<std::int16_t>(v * 20000.0f - 10000.0f));
    }
  }
  FieldView view(tessera::DType t) const {
    const void* p = t == tessera::DType::Float32   ? static_cast<const void*>(f32.data())
                    : t == tessera::DType::Float64 ? static_cast<const void*>(f64.data())
                    : t == tessera::DType::UInt8   ? static_cast<const void*>(u8.data())
                    : t == tessera::DType::UInt16  ? static_cast<const void*>(u16.data())
                                                   : static_cast<const void*>(i16.data());
    return FieldView::contiguous(p, t, NX, NY, NZ);
  }
};

/// What every scene shares: a camera on the field, a heterogeneous TF, a 24x16 image.
tessera::SceneDesc base_scene() {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(-0.9, -0.8, -0.7);
  s.geometry.spacing = Vec3(0.1);
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 12.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.5, 1.0}, {0.0, 0.3, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.6, 0.3), Color(0.3, 0.7, 0.95)});
  s.tf.roughness = tessera::ScalarTF({0.0, 1.0}, {0.2, 0.7});
  s.camera.position = Vec3(1.4, 0.9, -2.8);
  s.camera.look_at = Vec3(0.0, 0.0, 0.0);
  s.camera.fov_deg = 42.0;
  s.image = {W, H, 3, 0.0};
  s.options.seed = 77;
  s.options.frame = 5;
  s.options.threads = 2;
  s.options.tile = 8;
  return s;
}

void gradient_background(tessera::SceneDesc& s) {
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.top = Color(0.4, 0.5, 0.8);
  s.background.middle = Color(0.3);
  s.background.bottom = Color(0.05);
  s.background.up = Vec3(0.0, 1.0, 0.0);
}

struct GoldenScene {
  std::string name;
  tessera::DType dtype;
  std::function<void(tessera::SceneDesc&)> edit;
};

std::vector<GoldenScene> golden_scenes() {
  using tessera::DType;
  using tessera::Shading;
  return {
      {"delta_ratio_hybrid_multiple", DType::Float32,
       [](tessera::SceneDesc& s) {
         // Every emitter at once: rect, sphere, emitting gradient background, emission TF
         s.tf.specular = tessera::ColorTF::constant(Color(0.04));
         s.tf.emission = tessera::ColorTF({0.0, 0.6, 1.0}, {Color(0.0), Color(0.0), Color(2.0, 0.5, 0.1)});
         s.lights.push_back(tessera::RectLightDesc{Vec3(0.0, 2.0, 0.0), Vec3(0.0), 1.5, 1.0, Color(5.0, 4.0, 3.0)});
         s.lights.push_back(tessera::SphereLightDesc{Vec3(-2.0, 0.5, -1.0), 0.4, Color(3.0, 3.0, 6.0)});
         gradient_background(s);
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.max_bounces = 12;
         s.integrator.shading = Shading::Hybrid;
         s.integrator.gradient_factor = 2.0;
         s.integrator.phase_g = 0.2;
         s.integrator.macrocell = 4;
       }},
      {"delta_deltashadow_phase_single", DType::UInt8,
       [](tessera::SceneDesc& s) {
         s.tf.lo = 0.0;
         s.tf.hi = 255.0;
         s.lights.push_back(tessera::SphereLightDesc{Vec3(1.5, 1.5, -1.5), 0.3, Color(20.0, 18.0, 15.0)});
         s.background.color = Color(0.1, 0.12, 0.2);
         s.integrator.shading = Shading::Phase;
         s.integrator.shadow = tessera::ShadowMode::Delta;
         s.integrator.phase_g = -0.3;
       }},
      {"raymarch_brdf_multiple", DType::UInt16,
       [](tessera::SceneDesc& s) {
         s.tf.lo = 0.0;
         s.tf.hi = 60000.0;
         s.tf.specular = tessera::ColorTF({0.0, 1.0}, {Color(0.02), Color(0.3)});
         s.lights.push_back(tessera::RectLightDesc{Vec3(-1.0, 2.0, -1.0), Vec3(0.0), 1.0, 2.0, Color(6.0)});
         s.background.color = Color(0.05);
         s.integrator.free_path = tessera::FreePath::Raymarch;
         s.integrator.step = 0.7;
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.max_bounces = 5;
         s.integrator.shading = Shading::Brdf;
       }},
      {"envmap_global_majorant_phase", DType::Float64,
       [](tessera::SceneDesc& s) {
         // An environment map as the only light, one global majorant cell
         s.tf.lo = 0.25;
         s.tf.hi = 0.75;
         auto img = std::make_shared<tessera::Image>();
         img->width = 16;
         img->height = 8;
         for (int y = 0; y < img->height; ++y)
           for (int x = 0; x < img->width; ++x) {
             const float b = (x == 3 && y == 2) ? 40.0f : 0.2f + 0.05f * static_cast<float>(x % 4);
             img->rgba.insert(img->rgba.end(), {b, 0.8f * b, 0.5f + 0.1f * static_cast<float>(y), 1.0f});
           }
         s.background.type = tessera::BackgroundType::EnvMap;
         s.background.envmap = img;
         s.background.up = Vec3(0.0, 1.0, 0.0);
         s.background.intensity = 0.7;
         s.integrator.majorant = tessera::MajorantMode::Global;
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.max_bounces = 6;
         s.integrator.shading = Shading::Phase;
         s.integrator.phase_g = 0.5;
       }},
      {"adaptive_hybrid_emission", DType::Float32,
       [](tessera::SceneDesc& s) {
         s.image.spp = 24;
         s.image.target_error = 0.08;
         s.tf.emission = tessera::ColorTF({0.0, 0.5, 1.0}, {Color(0.0), Color(0.5), Color(1.0, 0.8, 0.2)});
         s.lights.push_back(tessera::RectLightDesc{Vec3(0.0, -2.0, 0.5), Vec3(0.0), 1.0, 1.0, Color(8.0)});
         gradient_background(s);
         s.integrator.shading = Shading::Hybrid;
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.max_bounces = 4;
       }},
      {"thin_lens_brdf_no_roulette", DType::Int16,
       [](tessera::SceneDesc& s) {
         s.tf.lo = -10000.0;
         s.tf.hi = 10000.0;
         s.camera.aperture = 0.08;
         s.camera.focus_distance = 2.5;
         s.lights.push_back(tessera::RectLightDesc{Vec3(2.0, 1.0, -1.0), Vec3(0.0), 0.8, 0.8, Color(10.0, 8.0, 6.0)});
         s.lights.push_back(tessera::SphereLightDesc{Vec3(-1.5, -1.5, 1.0), 0.25, Color(10.0)});
         s.background.color = Color(0.02);
         s.integrator.shading = Shading::Brdf;
         s.integrator.shadow_roulette = false;
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.max_bounces = 3;
       }},
      {"emission_only_no_lights", DType::Float32,
       [](tessera::SceneDesc& s) {
         // No light at all (black background): only the emission TF lights the image
         s.tf.emission = tessera::ColorTF({0.0, 1.0}, {Color(0.0), Color(3.0, 1.0, 0.5)});
         s.integrator.scattering = tessera::Scattering::Multiple;
         s.integrator.shading = Shading::Phase;
       }},
      {"culled_tiles_hidden_background", DType::Float32,
       [](tessera::SceneDesc& s) {
         // A distant camera: the field covers a few tiles, the rest are culled; the
         // background lights the medium but is hidden from the camera
         s.camera.position = Vec3(3.0, 2.0, -6.0);
         s.camera.fov_deg = 30.0;
         s.options.tile = 4;
         s.options.order = tessera::TileOrder::Morton;
         s.background.color = Color(0.6, 0.5, 0.4);
         s.background.visible = false;
         s.lights.push_back(tessera::SphereLightDesc{Vec3(0.0, 3.0, 0.0), 0.5, Color(4.0)});
         s.integrator.shading = Shading::Hybrid;
       }},
  };
}

/// The counters of a render as one line of text, in the golden counters file's format.
std::string counter_line(const std::string& name, const tessera::RenderStats& st) {
  std::ostringstream o;
  o << name << " samples " << st.samples << " free_flight " << st.free_flight_lookups << " transmittance "
    << st.transmittance_lookups << " gradient " << st.gradient_lookups << " real " << st.real_collisions << " null "
    << st.null_collisions << " discarded " << st.discarded_samples << " stalled " << st.stalled_paths
    << " tiles_skipped " << st.tiles_skipped;
  return o.str();
}

/// RGBA, then variance, then sample count per pixel: float32 as the machine stores them
/// (little endian on every platform the project builds on).
std::vector<char> image_bytes(const tessera::Image& im) {
  std::vector<char> out;
  for (const std::vector<float>* v : {&im.rgba, &im.variance, &im.samples}) {
    const char* p = reinterpret_cast<const char*>(v->data());
    out.insert(out.end(), p, p + v->size() * sizeof(float));
  }
  return out;
}

std::string golden_dir() { return std::string(TESSERA_TEST_DATA_DIR) + "/golden"; }

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("golden scenes render to the stored bytes and counters", "[golden][determinism][render]") {
  const Field field;
  const bool update = std::getenv("TESSERA_UPDATE_GOLDEN") != nullptr;
  std::string counters;
  for (const GoldenScene& g : golden_scenes()) {
    tessera::SceneDesc s = base_scene();
    g.edit(s);
    const tessera::PreparedScene ps = tessera::prepare(field.view(g.dtype), s);
    tessera::RenderStats st;
    const tessera::Image im = tessera_test::render_film(ps, &st).resolve();
    const std::vector<char> bytes = image_bytes(im);
    const std::string path = golden_dir() + "/" + g.name + ".f32";
    counters += counter_line(g.name, st) + "\n";
    INFO("scene " << g.name);
    // Not a trivial image: something was hit and lit
    CHECK(st.real_collisions > 0);
    if (update) {
      std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      continue;
    }
    const std::vector<char> stored = read_bytes(path);
    REQUIRE(stored.size() == bytes.size());
    CHECK(std::memcmp(stored.data(), bytes.data(), bytes.size()) == 0);
  }
  const std::string counters_path = golden_dir() + "/counters.txt";
  if (update) {
    std::ofstream(counters_path) << counters;
    WARN("golden images re-made in " << golden_dir());
    return;
  }
  const std::vector<char> stored = read_bytes(counters_path);
  CHECK(std::string(stored.begin(), stored.end()) == counters);
}
