// Denoising inputs (image.denoise): the first collision's albedo and normal accumulated beside
// the colour, deterministic like it and leaving it bit-identical; the EXR's denoised layer;
// the memory estimate; the library lookup order (denoiser.h). The denoiser itself (does it
// bring an 8-spp image closer to a converged one) is tests/denoise/, skipped without OIDN.
#include <tessera/denoiser.h>
#include <tessera/image_io.h>
#include <tessera/memory_estimate.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "scoped_env.h"
#include "temp_dir.h"
#include "test_support.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

using tessera::Color;
using tessera::FieldView;
using tessera::Vec3;

namespace {

constexpr int NX = 20, NY = 18, NZ = 16;

/// Hybrid shading with one constant diffuse colour, a rect light and a visible background:
/// pixels that miss, pixels that hit, surface-like and phase-like collisions.
tessera::SceneDesc aux_scene() {
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(-1.0, -0.9, -0.8);
  s.geometry.spacing = Vec3(0.1);
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 15.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.5, 1.0}, {0.0, 0.3, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.2, 0.5, 0.8));
  s.camera.position = Vec3(1.5, 1.0, -3.0);
  s.camera.look_at = Vec3(0.0, 0.0, 0.0);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.0, 2.0, 0.0), Vec3(0.0, 0.0, 0.0), 1.5, 1.0, Color(5.0, 4.0, 3.0)});
  s.background.type = tessera::BackgroundType::Constant;
  s.background.color = Color(0.3);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 2.0;
  s.image = {37, 29, 4, 0.0};
  s.image.denoise = true;
  s.options.seed = 99;
  return s;
}

tessera::Film render_film(const FieldView& view, tessera::SceneDesc s, bool aux, int threads, int tile) {
  s.options.threads = threads;
  s.options.tile = tile;
  const tessera::PreparedScene ps = tessera::prepare(view, s);
  tessera::Film film(s.image.width, s.image.height, aux);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  return film;
}

bool same_bytes(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

using tessera_test::ScopedEnv;

}  // namespace

TEST_CASE("denoise aux buffers leave the colour bit-identical and are deterministic", "[denoise][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  for (const double target_error : {0.0, 0.05}) {
    tessera::SceneDesc s = aux_scene();
    s.image.target_error = target_error;  // adaptive sampling draws its samples differently
    INFO("target_error " << target_error);
    const tessera::Film plain = render_film(view, s, false, 2, 8);
    const tessera::Film ref = render_film(view, s, true, 1, 8);
    REQUIRE(ref.has_aux());
    REQUIRE_FALSE(plain.has_aux());
    // The colour sums do not depend on whether the aux sums are kept
    REQUIRE(same_bytes(plain.pixels().data(), ref.pixels().data(), plain.pixels().size() * sizeof(tessera::PixelSums)));
    // The aux sums are the same bit for bit for any thread count and tile edge
    for (const int threads : {1, 2, 4})
      for (const int tile : {1, 8, 0}) {
        INFO("threads " << threads << " tile " << tile);
        const tessera::Film f = render_film(view, s, true, threads, tile);
        CHECK(same_bytes(f.aux().data(), ref.aux().data(), f.aux().size() * sizeof(tessera::AuxSums)));
        CHECK(same_bytes(f.pixels().data(), ref.pixels().data(), f.pixels().size() * sizeof(tessera::PixelSums)));
      }
  }
}

TEST_CASE("denoise aux buffers hold the first collision's albedo and normal", "[denoise][render]") {
  const std::vector<float> field = tessera_test::blobby_field(NX, NY, NZ);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, NX, NY, NZ);
  const tessera::SceneDesc s = aux_scene();
  const tessera::Film film = render_film(view, s, true, 2, 8);
  const tessera::Image img = film.resolve();
  const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
  REQUIRE(img.albedo.size() == n * 3);
  REQUIRE(img.normal.size() == n * 3);
  const Color diffuse(0.2, 0.5, 0.8);
  int hit = 0, missed = 0, with_normal = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // A camera sample's alpha is 1 iff it met a real collision, which is where albedo and
    // normal are recorded: the mean albedo is alpha times the constant diffuse colour, and
    // the mean normal (unit vectors, or 0) is no longer than alpha.
    const double a = img.rgba[4 * i + 3];
    for (int c = 0; c < 3; ++c) CHECK(img.albedo[3 * i + c] == Approx(a * diffuse[c]).margin(1e-6));
    const Vec3 nrm(img.normal[3 * i], img.normal[3 * i + 1], img.normal[3 * i + 2]);
    CHECK(glm::length(nrm) <= a + 1e-6);
    if (a == 0.0) {
      ++missed;
      CHECK(glm::length(nrm) == 0.0);
    } else {
      ++hit;
      with_normal += glm::length(nrm) > 0.0;
    }
  }
  CHECK(hit > 0);
  CHECK(missed > 0);
  CHECK(with_normal > 0);

  // Phase shading has no gradient normal: every normal is 0, the albedo is still there
  tessera::SceneDesc phase = s;
  phase.integrator.shading = tessera::Shading::Phase;
  const tessera::Image p = render_film(view, phase, true, 2, 8).resolve();
  for (const float v : p.normal) REQUIRE(v == 0.0f);
  float albedo_max = 0.0f;
  for (const float v : p.albedo) albedo_max = std::max(albedo_max, v);
  CHECK(albedo_max > 0.0f);
}

TEST_CASE("EXR keeps RGBA and adds the denoised layer, PNG shows the denoised image", "[denoise][image_io]") {
  tessera_test::TempDir dir;
  tessera::Image img;
  img.width = 5;
  img.height = 3;
  img.rgba.assign(5 * 3 * 4, 0.25f);
  for (std::size_t i = 0; i < 15; ++i) img.rgba[4 * i] = static_cast<float>(i);
  img.denoised.resize(5 * 3 * 3);
  for (std::size_t i = 0; i < img.denoised.size(); ++i) img.denoised[i] = 0.5f + static_cast<float>(i);
  const std::string exr = dir.file("d.exr");
  tessera::write_exr(exr, img);
  const tessera::Image back = tessera::read_exr(exr);
  CHECK(back.rgba == img.rgba);
  CHECK(back.denoised == img.denoised);

  // Without the layer nothing is added, and a wrong-sized layer is refused naming it
  img.denoised.clear();
  tessera::write_exr(exr, img);
  CHECK(tessera::read_exr(exr).denoised.empty());
  img.denoised.assign(7, 0.0f);
  CHECK_THROWS_WITH(tessera::write_exr(exr, img), Catch::Contains("denoised has 7 floats"));

  // PNG: the same RGBA with two different denoised layers gives two different files
  img.denoised.assign(15 * 3, 0.0f);
  tessera::write_png(dir.file("black.png"), img);
  img.denoised.assign(15 * 3, 1.0f);
  tessera::write_png(dir.file("white.png"), img);
  const auto size = [&](const char* name) { return std::filesystem::file_size(dir.file(name)); };
  REQUIRE(size("black.png") > 0);
  std::ifstream a(dir.file("black.png"), std::ios::binary), b(dir.file("white.png"), std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(a)), {}), sb((std::istreambuf_iterator<char>(b)), {});
  CHECK(sa != sb);
}

TEST_CASE("memory estimate counts the denoise buffers", "[denoise][memory]") {
  tessera::RenderFootprint f;
  f.width = 512;
  f.height = 512;
  const std::uint64_t off = tessera::estimate_render_memory(f).total();
  f.denoise = true;
  const tessera::MemoryEstimate on = tessera::estimate_render_memory(f);
  const std::uint64_t pixels = 512 * 512;
  // Film aux sums, three float layers and OIDN's working memory at least
  CHECK(on.total() >= off + pixels * (sizeof(tessera::AuxSums) + 9 * sizeof(float) + tessera::kDenoiserBytesPerPixel));
  CHECK(on.describe().find("denoise buffers") != std::string::npos);
}

TEST_CASE("memory estimate: OIDN's working memory is counted per pixel up to the cap where OIDN tiles",
          "[denoise][memory]") {
  const auto oidn_part = [](int w, int h) {
    tessera::RenderFootprint f;
    f.width = w;
    f.height = h;
    f.formats = {tessera::ImageFormat::Png};  // no EXR line buffers for the extra channels
    const std::uint64_t off = tessera::estimate_render_memory(f).total();
    f.denoise = true;
    const std::uint64_t pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    // Less the film's aux sums and the three float layers: OIDN's part
    return tessera::estimate_render_memory(f).total() - off - pixels * (sizeof(tessera::AuxSums) + 9 * sizeof(float));
  };
  // Below the cap: per pixel, plus the fixed cost
  CHECK(oidn_part(1024, 1024) == 1024u * 1024u * tessera::kDenoiserBytesPerPixel + tessera::kDenoiserFixedBytes);
  // A 16384^2 image (OIDN tiles it): the cap, not 268 million pixels' worth
  CHECK(oidn_part(16384, 16384) == tessera::kDenoiserMaxWorkingBytes + tessera::kDenoiserFixedBytes);
  CHECK(tessera::kDenoiserMaxWorkingBytes >= (std::uint64_t(tessera::kDenoiserMaxMemoryMB) << 20));
}

TEST_CASE("OIDN lookup order: TESSERA_OIDN_LIBRARY alone, else the soname, then pyoidn of python3 on PATH",
          "[denoise][lookup]") {
  tessera_test::TempDir dir;
  // A venv-like tree: bin/python3 and lib/python3.11/site-packages/pyoidn/oidn/lib/
  const auto venv = dir.path() / "venv";
  std::filesystem::create_directories(venv / "bin");
  const auto lib_dir = venv / "lib/python3.11/site-packages/pyoidn/oidn/lib";
  std::filesystem::create_directories(lib_dir);
  const std::string lib = (lib_dir / "libOpenImageDenoise.so.2").string();
  std::ofstream(lib) << "not a library";
  const std::string py = (venv / "bin/python3").string();
  std::ofstream(py) << "#!/bin/sh\n";
  std::filesystem::permissions(py, std::filesystem::perms::owner_all);

  {
    const ScopedEnv env("TESSERA_OIDN_LIBRARY", std::string("/nowhere/libOpenImageDenoise.so.2"));
    CHECK(tessera::oidn_search_paths() == std::vector<std::string>{"/nowhere/libOpenImageDenoise.so.2"});
  }
  {
    const ScopedEnv env("TESSERA_OIDN_LIBRARY", std::nullopt);
    const ScopedEnv path("PATH", (dir.path() / "empty").string() + ":" + (venv / "bin").string());
    const ScopedEnv home("HOME", dir.path().string());
    const std::vector<std::string> paths = tessera::oidn_search_paths();
    REQUIRE(paths.size() >= 2);
    CHECK(paths[0] == "libOpenImageDenoise.so.2");
    CHECK(std::filesystem::equivalent(paths[1], lib));
  }
  {
    // An empty TESSERA_OIDN_LIBRARY counts as unset
    const ScopedEnv env("TESSERA_OIDN_LIBRARY", std::string(""));
    const ScopedEnv path("PATH", (dir.path() / "empty").string());
    const ScopedEnv home("HOME", dir.path().string());
    const std::vector<std::string> paths = tessera::oidn_search_paths();
    REQUIRE_FALSE(paths.empty());
    CHECK(paths[0] == "libOpenImageDenoise.so.2");
    for (const std::string& p : paths) CHECK(p.find(dir.path().string()) == std::string::npos);
  }
}
