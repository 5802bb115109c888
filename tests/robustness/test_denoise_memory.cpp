// Robustness: memory_limit_mb includes the denoiser (docs/insitu.md "Limits and failure").
// Denoised CLI renders of several sizes run with tessera.memory_limit_mb at their own estimate
// (as printed, three digits, rounded up): each passes the check, and its peak RSS, less the
// peak of a tiny render without denoising (the process and its libraries), stays under the
// limit. Skipped
// without Open Image Denoise; under AddressSanitizer the RSS is not compared (its shadow
// memory and quarantine are not the program's).
#include "cli_run.h"
#include "measured_child.h"

#include "../insitu/insitu_test_support.h"

#include <tessera/denoiser.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <string>

using tessera_test::TempDir;

namespace {

#ifdef TESSERA_RENDER_EXE
/// A 16^3 blob and one render of w x h at 1 spp writing EXR and PNG, under `limit_mb`.
void write_scene(const TempDir& dir, int w, int h, bool denoise, long limit_mb) {
  using namespace tessera::insitu::test;
  const std::vector<float> v = to_float(blob_values(16));
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml", "tessera:\n  output_dir: results\n  memory_limit_mb: " + std::to_string(limit_mb) +
                              "\n"
                              "volume: {file: blob.raw, dims: [16, 16, 16], dtype: float32, spacing: [0.1, 0.1, 0.1]}\n"
                              "renders:\n  - name: d\n    image: {width: " +
                              std::to_string(w) + ", height: " + std::to_string(h) +
                              ", spp: 1, denoise: " + (denoise ? "true" : "false") +
                              "}\n    camera: {position: [0.4, 0.5, 2.5], look_at: center}\n"
                              "    transfer_function: {opacity: [[0, 0], [1, 1]]}\n"
                              "    output: {file: d, formats: [exr, png]}\n");
}

/// The estimate in MiB from "needs an estimated 1.62 GiB (" (format_bytes), -1 if absent.
double estimate_mib(const std::string& err) {
  const std::string key = "needs an estimated ";
  const std::size_t p = err.find(key);
  if (p == std::string::npos) return -1.0;
  std::size_t used = 0;
  const double v = std::stod(err.substr(p + key.size()), &used);
  const std::string unit = err.substr(p + key.size() + used + 1, 3);
  return unit == "GiB" ? v * 1024.0 : unit == "MiB" ? v : unit == "KiB" ? v / 1024.0 : -1.0;
}
#endif

}  // namespace

#ifdef TESSERA_RENDER_EXE
TEST_CASE("denoise memory: peak RSS of denoised renders stays under memory_limit_mb set at the estimate",
          "[robustness][denoise][memory]") {
  std::string lib;
  try {
    lib = tessera::require_denoiser();
  } catch (const tessera::DenoiserUnavailable& e) {
    WARN("skipped, Open Image Denoise not found: " << e.what());
    return;
  }
  // The child loads the same library
  const std::vector<std::string> env = {lib.find('/') == std::string::npos ? "TESSERA_TEST_UNUSED=1"
                                                                           : "TESSERA_OIDN_LIBRARY=" + lib};
  const std::vector<std::string> argv = {TESSERA_RENDER_EXE, "scene.yaml", "--quiet"};

  TempDir base_dir;
  write_scene(base_dir, 16, 16, false, 0);
  const tessera_test::MeasuredRun base = tessera_test::run_measured(base_dir, argv, env);
  REQUIRE(base.status == 0);

  const int sizes[][2] = {{256, 256}, {512, 256}, {512, 512}};
  for (const auto& s : sizes) {
    INFO(s[0] << "x" << s[1]);
    TempDir dir;
    // The estimate, from the refusal under a 1 MiB limit
    write_scene(dir, s[0], s[1], true, 1);
    const tessera_test::MeasuredRun probe = tessera_test::run_measured(dir, argv, env);
    INFO(probe.err);
    REQUIRE(probe.status == 1);
    const double est = estimate_mib(probe.err);
    REQUIRE(est > 0.0);
    const long limit_mb = static_cast<long>(std::ceil(est * 1.005)) + 1;  // est has 3 digits

    write_scene(dir, s[0], s[1], true, limit_mb);
    const tessera_test::MeasuredRun r = tessera_test::run_measured(dir, argv, env);
    INFO(r.err);
    REQUIRE(r.status == 0);
    const double growth_mib = static_cast<double>(r.peak_rss_kib - base.peak_rss_kib) / 1024.0;
    INFO("estimate " << est << " MiB, limit " << limit_mb << " MiB, peak RSS growth " << growth_mib << " MiB");
#if !defined(__SANITIZE_ADDRESS__)
    CHECK(growth_mib <= static_cast<double>(limit_mb));
#endif
  }
}
#endif
