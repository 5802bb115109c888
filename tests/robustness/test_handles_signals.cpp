// Robustness: no signal escapes an image write (SIGXFSZ under a file-size limit, SIGPIPE) and
// adapter handles are validated (double close, execute after close, foreign pointers).
#include "../insitu/insitu_test_support.h"
#include "cli_run.h"
#include "file_size_limit.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>
#include <tessera/signal_guard.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

using tessera_test::FileSizeLimit;

using tessera_test::count_files;

bool pending(int sig) {
  sigset_t set;
  sigemptyset(&set);
  sigpending(&set);
  return sigismember(&set, sig) == 1;
}

}  // namespace

TEST_CASE("SIGXFSZ: an image write past the file-size limit is TESSERA_ERROR_IO, no temp file left",
          "[robustness][signals]") {
  TempDir dir;
  const std::string out = dir.file("out");
  const std::string cfg = dir.write(
      "a.yaml",
      config_yaml(out, render_yaml("big", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr, png]}\n",
                                   "density", 64, 1)));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);  // writes the effective config
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  tessera_status s = TESSERA_OK;
  {
    const FileSizeLimit limit(1000);  // a 64x64 float EXR is far larger
    REQUIRE(limit.ok());
    s = tessera_execute(a, 0, 0.0, &g, &f, 1);
    CHECK_FALSE(pending(SIGXFSZ));  // consumed, not left to fire at the old mask
  }
  // Still alive: the write failed with EFBIG instead
  CHECK(s == TESSERA_ERROR_IO);
  const std::string err = tessera_last_error(a);
  CHECK_THAT(err, Contains("render 'big' at step 0") && Contains("cannot write") && Contains("big_0000.exr") &&
                      Contains("File too large"));
  CHECK(count_files(out, ".tmp") == 0);
  CHECK_FALSE(fs::exists(out + "/big_0000.exr"));
  // And the next call, without the limit, writes
  CHECK(tessera_execute(a, 1, 0.0, &g, &f, 1) == TESSERA_OK);
  CHECK(fs::exists(out + "/big_0001.exr"));
  CHECK(fs::exists(out + "/big_0001.png"));
  CHECK(tessera_close(a) == TESSERA_OK);
}

TEST_CASE("SIGXFSZ: the PNG and EXR writers fail with EFBIG, and a pending signal of the caller stays",
          "[robustness][signals]") {
  TempDir dir;
  tessera::Image img;
  img.width = img.height = 64;
  img.rgba.assign(64 * 64 * 4, 0.5f);
  for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = static_cast<float>((i * 7919) % 1000) / 1000.0f;
  {
    const FileSizeLimit limit(1000);
    REQUIRE(limit.ok());
    CHECK_THROWS_WITH(tessera::write_png(dir.file("a.png"), img), Contains("File too large"));
    CHECK_THROWS_WITH(tessera::write_exr(dir.file("a.exr"), img), Contains("cannot write"));
  }
  CHECK(count_files(dir.path().string(), ".tmp") == 0);
  CHECK(count_files(dir.path().string(), "a.") == 0);

  // A SIGPIPE the thread had pending (blocked) before the guard is not consumed by it
  sigset_t pipe_set, old;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
  raise(SIGPIPE);
  REQUIRE(pending(SIGPIPE));
  { const tessera::BlockWriteSignals guard; }
  CHECK(pending(SIGPIPE));
  const timespec zero{0, 0};
  CHECK(sigtimedwait(&pipe_set, nullptr, &zero) == SIGPIPE);
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("SIGXFSZ: tessera-render under ulimit -f exits 1 with the message, no temp file",
          "[robustness][signals][cli]") {
  TempDir dir;
  const std::vector<float> v = to_float(blob_values(16));
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml",
            "tessera:\n  output_dir: results\n"
            "volume: {file: blob.raw, dims: [16, 16, 16], dtype: float32, spacing: [0.1, 0.1, 0.1]}\n"
            "renders:\n" +
                render_yaml("big", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr, png]}\n", "", 64, 1));
  // ulimit -f counts 512-byte blocks: 2 = 1024 bytes. A SIGXFSZ that escaped would show as
  // status 128 + 25 from `timeout`
  const tessera_test::CliRun r = tessera_test::run_cli(dir, "scene.yaml --quiet", "ulimit -f 2 &&");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("tessera-render: error:") && Contains("File too large"));
  CHECK(count_files(dir.file("results"), ".tmp") == 0);
  CHECK(count_files(dir.file("results"), "big") == 0);
}
#endif

TEST_CASE("handles: double close, execute after close and foreign pointers are errors", "[robustness][handles]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", "", "density", 16, 1)));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  CHECK(tessera_close(a) == TESSERA_OK);
  CHECK(tessera_close(a) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(tessera_last_error(a)), Contains("adapter was closed"));
  CHECK_THAT(std::string(tessera_last_error(nullptr)), Contains("tessera_close") && Contains("adapter was closed"));

  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  CHECK(tessera_execute(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_CONFIG);
  CHECK(tessera_execute_final(a, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_CONFIG);
  CHECK(tessera_field_unchanged(a, "density") == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(tessera_last_error(a)), Contains("adapter was closed"));

  // A new adapter never takes the closed one's address
  tessera_adapter* b = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &b) == TESSERA_OK);
  CHECK(b != a);
  CHECK(tessera_execute(b, 0, 0.0, &g, &f, 1) == TESSERA_OK);
  CHECK(tessera_execute(a, 1, 0.0, &g, &f, 1) == TESSERA_ERROR_CONFIG);
  CHECK(tessera_close(b) == TESSERA_OK);

  // Pointers tessera_open never returned
  alignas(16) unsigned char junk[64] = {};
  auto* bogus = reinterpret_cast<tessera_adapter*>(junk);
  CHECK(tessera_execute(bogus, 0, 0.0, &g, &f, 1) == TESSERA_ERROR_CONFIG);
  CHECK(tessera_close(bogus) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(std::string(tessera_last_error(bogus)), Contains("not an adapter returned by tessera_open"));
  CHECK(tessera_close(nullptr) == TESSERA_OK);
}

TEST_CASE("handles: the C++ Adapter refuses execute after close", "[robustness][handles]") {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", "", "density", 16, 1)));
  tessera::insitu::Adapter ad;
  REQUIRE(ad.open(cfg, -1) == TESSERA_OK);
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  CHECK(ad.close() == TESSERA_OK);
  CHECK(ad.close() == TESSERA_OK);  // idempotent for the owning object
  CHECK(ad.execute(0, 0.0, g, std::span<const tessera_field>(&f, 1)) == TESSERA_ERROR_CONFIG);
  CHECK_THAT(ad.last_error(), Contains("adapter was closed"));
  tessera::insitu::Adapter moved = std::move(ad);
  CHECK(ad.execute(0, 0.0, g, std::span<const tessera_field>(&f, 1)) == TESSERA_ERROR_CONFIG);  // NOLINT: moved from
  CHECK_FALSE(ad.is_open());
}
