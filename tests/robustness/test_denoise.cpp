// Robustness: image.denoise (docs/cli.md "Denoising"). Asked for and not found, the CLI
// fails before rendering with a message naming what was tried and how to install OIDN, for a
// missing file and for a library that is not OIDN, without a crash; the adapter fails at
// tessera_open naming renders[i].image.denoise. Found (CI: pyoidn in the project venv), the
// EXR's RGBA is bit-identical to a render without denoising and gains denoised.R/G/B.
#include "../insitu/insitu_test_support.h"
#include "cli_run.h"
#include "denoise_scene.h"

#include <tessera/denoiser.h>
#include <tessera/image_io.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using namespace tessera::insitu::test;
using namespace tessera_test::denoise;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

/// The path of a shared library this process has loaded whose name contains `part`, "".
std::string loaded_library(const char* part) {
  struct Find {
    const char* part;
    std::string path;
  } find{part, ""};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto* f = static_cast<Find*>(data);
        if (info->dlpi_name && std::string(info->dlpi_name).find(f->part) != std::string::npos) {
          f->path = info->dlpi_name;
          return 1;
        }
        return 0;
      },
      &find);
  return find.path;
}

}  // namespace

TEST_CASE("denoise: TESSERA_OIDN_LIBRARY naming a missing file fails before rendering, naming it",
          "[robustness][denoise]") {
  TempDir dir;
  write_cli_scene(dir, true);
  const tessera_test::CliRun r = tessera_test::run_cli(
      dir, "scene.yaml --quiet", "TESSERA_OIDN_LIBRARY=/nonexistent/libOpenImageDenoise.so.2", 30);
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("tessera-render: error: scene.yaml: render 'd': image.denoise: cannot load Intel Open "
                             "Image Denoise from TESSERA_OIDN_LIBRARY=/nonexistent/libOpenImageDenoise.so.2"));
  CHECK_THAT(r.err, Contains("python3 -m pip install pyoidn"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one line
  CHECK_FALSE(fs::exists(dir.path() / "results"));           // nothing rendered, nothing written
}

TEST_CASE("denoise: TESSERA_OIDN_LIBRARY naming a library that is not OIDN is refused, no crash",
          "[robustness][denoise]") {
  // libz: loaded by this process through libpng/OpenEXR, so it exists on this machine
  const std::string libz = loaded_library("libz.so");
  REQUIRE_FALSE(libz.empty());
  TempDir dir;
  write_cli_scene(dir, true);
  const tessera_test::CliRun r = tessera_test::run_cli(dir, "scene.yaml --quiet", "TESSERA_OIDN_LIBRARY=" + libz, 30);
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("TESSERA_OIDN_LIBRARY=" + libz +
                             ": not Open Image Denoise 2.x (it has no function oidnNewDevice)"));
  CHECK_FALSE(fs::exists(dir.path() / "results"));
  // A file that is not a library at all
  dir.write("fake.so", "not an ELF file");
  const tessera_test::CliRun f =
      tessera_test::run_cli(dir, "scene.yaml --quiet", "TESSERA_OIDN_LIBRARY=" + dir.file("fake.so"), 30);
  CHECK(f.status == 1);
  CHECK_THAT(f.err, Contains("cannot load Intel Open Image Denoise from TESSERA_OIDN_LIBRARY=" + dir.file("fake.so")));
}

TEST_CASE("denoise: not found anywhere, the error lists the places tried and how to install it",
          "[robustness][denoise]") {
  TempDir dir;
  write_cli_scene(dir, true);
  fs::create_directories(dir.path() / "home");
  // No python3 with pyoidn on PATH, no user site: only a system-wide OIDN could be found
  const tessera_test::CliRun r = tessera_test::run_cli(
      dir, "scene.yaml --quiet",
      "env -u TESSERA_OIDN_LIBRARY HOME=" + dir.file("home") + " PATH=/nonexistent:/usr/bin:/bin", 30);
  if (r.status == 0) {
    WARN("Open Image Denoise was found in a system location; the not-found message is not tested here");
    return;
  }
  CHECK(r.status == 1);
  CHECK_THAT(r.err,
             Contains("image.denoise: Intel Open Image Denoise 2.x not found (tried TESSERA_OIDN_LIBRARY: unset; "
                      "libOpenImageDenoise.so.2: "));
  CHECK_THAT(r.err, Contains("install it with `python3 -m pip install pyoidn`"));
  CHECK_THAT(r.err, Contains("TESSERA_OIDN_LIBRARY=/path/to/libOpenImageDenoise.so.2"));
  CHECK_FALSE(fs::exists(dir.path() / "results"));
}

TEST_CASE("denoise: the EXR's RGBA is bit-identical with denoise on and off, denoised.R/G/B added",
          "[robustness][denoise]") {
  try {
    tessera::require_denoiser();
  } catch (const tessera::DenoiserUnavailable& e) {
    WARN("skipped, Open Image Denoise not found: " << e.what());
    return;
  }
  TempDir off, on;
  write_cli_scene(off, false);
  write_cli_scene(on, true);
  const tessera_test::CliRun a = tessera_test::run_cli(off, "scene.yaml --quiet");
  const tessera_test::CliRun b = tessera_test::run_cli(on, "scene.yaml --quiet");
  REQUIRE(a.status == 0);
  REQUIRE(b.status == 0);
  const tessera::Image plain = tessera::read_exr(off.file("results/d.exr"));
  const tessera::Image den = tessera::read_exr(on.file("results/d.exr"));
  CHECK(plain.rgba == den.rgba);
  CHECK(plain.denoised.empty());
  REQUIRE(den.denoised.size() == den.rgba.size() / 4 * 3);
  CHECK(den.denoised != std::vector<float>(den.denoised.size(), 0.0f));
  CHECK(tessera_test::slurp(off.file("results/d.png")) != tessera_test::slurp(on.file("results/d.png")));
}

TEST_CASE("denoise: the adapter fails at tessera_open without OIDN, else writes the layer, Cinema views too",
          "[robustness][denoise]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cinema = "    output: {file: \"{name}_{step:04d}\", formats: [exr, png], "
                             "cinema: {azimuth: [0, 90], elevation: [0]}}\n";
  const std::string cfg =
      dir.write("a.yaml", config_yaml(out, with_denoise(render_yaml("d", "{every: 1}", cinema), true)));
  bool available = true;
  try {
    tessera::require_denoiser();  // this process's one lookup (denoiser.h)
  } catch (const tessera::DenoiserUnavailable&) {
    available = false;
  }
  tessera_adapter* a = nullptr;
  const tessera_status st = tessera_open(cfg.c_str(), -1, &a);
  if (!available) {
    CHECK(st == TESSERA_ERROR_CONFIG);
    CHECK(a == nullptr);
    CHECK_THAT(std::string(tessera_last_error(nullptr)),
               Contains("a.yaml: renders[0].image.denoise (render 'd'): ") && Contains("pip install pyoidn"));
    return;
  }
  REQUIRE(st == TESSERA_OK);
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  REQUIRE(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_OK);
  CHECK(tessera_close(a) == TESSERA_OK);
  const tessera::Image img = tessera::read_exr(out + "/d_0000.exr");
  CHECK(img.denoised.size() == img.rgba.size() / 4 * 3);
  // Every Cinema view is denoised like the main image
  int views = 0;
  for (const auto& e : fs::recursive_directory_iterator(out + "/d.cdb"))
    if (e.path().extension() == ".exr") {
      ++views;
      const tessera::Image v = tessera::read_exr(e.path().string());
      CHECK(v.denoised.size() == v.rgba.size() / 4 * 3);
    }
  CHECK(views == 2);
}
