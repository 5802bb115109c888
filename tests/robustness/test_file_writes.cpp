// Robustness: no corrupt file under a final name, ever. A file-size limit at every byte of a
// small EXR, PNG and text file, an injected ENOSPC at every byte, a full tmpfs and
// `prlimit --fsize` around tessera-render and an adapter driver: each failure is an error
// (exception, TESSERA_ERROR_IO, non-zero exit) naming the path, with no file under the final
// name (an older complete one left unchanged) and no temporary file left.
#include "../insitu/insitu_test_support.h"
#include "cli_run.h"
#include "file_size_limit.h"
#include "outputs/outputs.h"

#include <tessera/atomic_output.h>
#include <tessera/image_io.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::count_files;
using tessera_test::slurp;
namespace fs = std::filesystem;

namespace {

using tessera_test::FileSizeLimit;

/// detail::set_write_fault for the scope.
class InjectedFault {
 public:
  InjectedFault(std::uint64_t byte, int error, const std::string& suffix = "") {
    tessera::detail::set_write_fault(byte, error, suffix);
  }
  ~InjectedFault() { tessera::detail::clear_write_fault(); }
  InjectedFault(const InjectedFault&) = delete;
  InjectedFault& operator=(const InjectedFault&) = delete;
};

/// A 4x3 image with every channel the EXR writer knows, values all distinct.
tessera::Image tiny_image(float scale = 1.0f) {
  tessera::Image img;
  img.width = 4;
  img.height = 3;
  for (int i = 0; i < 12 * 4; ++i) img.rgba.push_back(scale * static_cast<float>((i * 37) % 101) / 50.0f);
  for (int i = 0; i < 12; ++i) img.variance.push_back(0.01f * static_cast<float>(i));
  for (int i = 0; i < 12; ++i) img.samples.push_back(static_cast<float>(4 + i));
  for (int i = 0; i < 12 * 3; ++i) img.denoised.push_back(scale * static_cast<float>((i * 13) % 29) / 20.0f);
  return img;
}

struct Writer {
  const char* name;
  std::function<void(const std::string&)> write;
};

/// The writers under test; `scale` changes the content (for the "older file survives" test).
std::vector<Writer> writers(float scale = 1.0f) {
  const tessera::Image img = tiny_image(scale);
  const std::string text = "time,phi,theta,FILE\n0," + std::to_string(scale) + ",0,a.png\n";
  return {
      {"exr", [img](const std::string& p) { tessera::write_exr(p + ".exr", img); }},
      {"png", [img](const std::string& p) { tessera::write_png(p + ".png", img); }},
      {"csv", [text](const std::string& p) { tessera::insitu::write_text_atomic(p + ".csv", text); }},
  };
}

/// For every limit n in [0, size): run `fail_at(n)` around the writer and collect the n at
/// which it did not throw with `expected`, left a file under the final name or a temporary.
template <class Around>
std::vector<std::string> faults_at_every_byte(const tessera_test::TempDir& dir, const Writer& w, std::uint64_t size,
                                              const std::string& expected, Around&& around) {
  std::vector<std::string> bad;
  const std::string base = dir.file("out");
  const std::string final_path = base + "." + w.name;
  for (std::uint64_t n = 0; n < size; ++n) {
    std::string message;
    around(n, [&] {
      try {
        w.write(base);
      } catch (const std::exception& e) {
        message = e.what();
      }
    });
    if (message.find(expected) == std::string::npos || message.find(final_path) == std::string::npos)
      bad.push_back("n=" + std::to_string(n) + ": message '" + message + "'");
    if (fs::exists(final_path)) bad.push_back("n=" + std::to_string(n) + ": file under the final name");
    if (count_files(dir.path().string(), ".tmp") != 0) bad.push_back("n=" + std::to_string(n) + ": temporary left");
    std::error_code ec;
    fs::remove(final_path, ec);
  }
  return bad;
}

}  // namespace

TEST_CASE("file writes: under a file-size limit at every byte, EXR, PNG and text writers fail and leave no file",
          "[robustness][writes]") {
  tessera_test::TempDir ref_dir, dir;
  for (const Writer& w : writers()) {
    DYNAMIC_SECTION(w.name) {
      // The complete file, written without a limit
      w.write(ref_dir.file("out"));
      const std::string ref = slurp(ref_dir.file(std::string("out.") + w.name));
      REQUIRE(ref.size() > 30);

      const std::vector<std::string> bad =
          faults_at_every_byte(dir, w, ref.size(), "File too large", [](std::uint64_t n, auto&& run) {
            const FileSizeLimit limit(static_cast<rlim_t>(n));
            REQUIRE(limit.ok());
            run();
          });
      for (std::size_t i = 0; i < bad.size() && i < 5; ++i) UNSCOPED_INFO(bad[i]);
      CHECK(bad.empty());

      // At the exact size it succeeds, and the file is the complete one
      {
        const FileSizeLimit limit(static_cast<rlim_t>(ref.size()));
        REQUIRE(limit.ok());
        CHECK_NOTHROW(w.write(dir.file("out")));
      }
      CHECK(slurp(dir.file(std::string("out.") + w.name)) == ref);
      if (std::string(w.name) == "exr") {
        const tessera::Image back = tessera::read_exr(dir.file("out.exr"));
        CHECK(same_pixels(back, tiny_image()));
        CHECK(back.denoised == tiny_image().denoised);
      }
    }
  }
}

TEST_CASE("file writes: ENOSPC at every byte fails each writer with the offset and leaves no file",
          "[robustness][writes]") {
  tessera_test::TempDir ref_dir, dir;
  for (const Writer& w : writers()) {
    DYNAMIC_SECTION(w.name) {
      w.write(ref_dir.file("out"));
      const std::uint64_t size = fs::file_size(ref_dir.file(std::string("out.") + w.name));
      const std::vector<std::string> bad =
          faults_at_every_byte(dir, w, size, "No space left on device", [](std::uint64_t n, auto&& run) {
            const InjectedFault fault(n, ENOSPC);
            run();
          });
      for (std::size_t i = 0; i < bad.size() && i < 5; ++i) UNSCOPED_INFO(bad[i]);
      CHECK(bad.empty());
    }
  }
  // The message names the byte offset
  const InjectedFault fault(7, EIO);
  CHECK_THROWS_WITH(tessera::write_file_atomically(dir.file("x.txt"), "0123456789"),
                    Contains("x.txt") && Contains("at byte 7") && Contains("Input/output error"));
}

TEST_CASE("file writes: an older complete file under the final name survives a failed write unchanged",
          "[robustness][writes]") {
  tessera_test::TempDir dir;
  const std::vector<Writer> old_writers = writers(1.0f), new_writers = writers(2.0f);
  for (std::size_t i = 0; i < old_writers.size(); ++i) {
    DYNAMIC_SECTION(old_writers[i].name) {
      const std::string final_path = dir.file(std::string("out.") + old_writers[i].name);
      old_writers[i].write(dir.file("out"));
      const std::string old_bytes = slurp(final_path);
      for (const std::uint64_t n : {0, 10, 30}) {  // all below the smallest file (39 bytes)
        {
          const FileSizeLimit limit(static_cast<rlim_t>(n));
          REQUIRE(limit.ok());
          CHECK_THROWS(new_writers[i].write(dir.file("out")));
        }
        {
          const InjectedFault fault(n, ENOSPC);
          CHECK_THROWS(new_writers[i].write(dir.file("out")));
        }
        CHECK(slurp(final_path) == old_bytes);
      }
      CHECK(count_files(dir.path().string(), ".tmp") == 0);
      // And a successful write replaces it
      new_writers[i].write(dir.file("out"));
      CHECK(slurp(final_path) != old_bytes);
    }
  }
}

TEST_CASE("file writes: AtomicOutputFile checks positioned writes, size and double commit", "[robustness][writes]") {
  tessera_test::TempDir dir;
  const std::string path = dir.file("p.bin");
  {
    tessera::AtomicOutputFile out(path);
    out.write("xxxxEFGH", 8);
    out.write_at(0, "ABCD", 4);  // a streaming writer going back to fill in a table
    CHECK(out.size() == 8);
    CHECK_FALSE(fs::exists(path));
    CHECK(fs::exists(out.temp_path()));
    out.commit();
    CHECK_THROWS_WITH(out.commit(), Contains("already committed"));
  }
  CHECK(slurp(path) == "ABCDEFGH");

  // A failed write is remembered: a caller that swallowed it still cannot commit
  {
    tessera::AtomicOutputFile out(dir.file("q.bin"));
    {
      const InjectedFault fault(2, ENOSPC);
      tessera::AtomicOutputFile armed(dir.file("q2.bin"));
      CHECK_THROWS(armed.write("abcd", 4));
      CHECK_THROWS_WITH(armed.commit(), Contains("No space left on device"));
    }
    out.write("abcd", 4);  // created before the fault was set: not affected
    out.commit();
  }
  CHECK(slurp(dir.file("q.bin")) == "abcd");
  CHECK_FALSE(fs::exists(dir.file("q2.bin")));

  // A leftover temporary name (a killed process whose pid came back) is skipped, not reused
  {
    std::string next;
    {
      const tessera::AtomicOutputFile probe(dir.file("r.bin"));  // ends in .tmp.<pid>.<k>
      const std::string& t = probe.temp_path();
      const std::size_t dot = t.rfind('.');
      next = t.substr(0, dot + 1) + std::to_string(std::stoul(t.substr(dot + 1)) + 1);
    }
    dir.write(fs::path(next).filename().string(), "someone else's");
    tessera::write_file_atomically(dir.file("r.bin"), "mine");
    CHECK(slurp(dir.file("r.bin")) == "mine");
    CHECK(slurp(next) == "someone else's");
    fs::remove(next);
  }

  // No directory, or a NUL in the name: an error naming the path, nothing created
  CHECK_THROWS_WITH(tessera::write_file_atomically(dir.file("missing/x.txt"), "a"),
                    Contains("missing/x.txt") && Contains("No such file or directory"));
  CHECK_THROWS_WITH(tessera::write_file_atomically(std::string("a\0b", 3), "a"), Contains("NUL"));
  CHECK(count_files(dir.path().string(), ".tmp") == 0);
}

TEST_CASE("file writes: the adapter returns TESSERA_ERROR_IO for the effective config, images and Cinema data.csv",
          "[robustness][writes]") {
  tessera_test::TempDir dir;
  const std::string out = dir.file("out");
  const std::string extra = "    output: {file: \"{name}_{step:04d}\", formats: [exr, png], cinema: {azimuth: [0]}}\n";
  const std::string cfg = dir.write("a.yaml", config_yaml(out, render_yaml("w", "", extra, "density", 8, 1)));
  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);

  // The effective config, written at open
  tessera_adapter* a = nullptr;
  {
    const InjectedFault fault(5, ENOSPC, "tessera_effective_config.yaml");
    CHECK(tessera_open(cfg.c_str(), -1, &a) == TESSERA_ERROR_IO);
  }
  CHECK(a == nullptr);
  CHECK_THAT(std::string(tessera_last_error(nullptr)),
             Contains("tessera_effective_config.yaml") && Contains("No space left on device"));
  CHECK_FALSE(fs::exists(out + "/tessera_effective_config.yaml"));

  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  // The EXR mid-file at step 0, the PNG at step 1
  int step = 0;
  for (const char* suffix : {".exr", ".png"}) {
    const InjectedFault fault(100, ENOSPC, suffix);
    CHECK(tessera_execute(a, step, 0.0, &g, &f, 1) == TESSERA_ERROR_IO);
    const std::string name = "w_000" + std::to_string(step) + suffix;
    CHECK_THAT(std::string(tessera_last_error(a)),
               Contains(name) && Contains("at byte 100") && Contains("No space left"));
    CHECK_FALSE(fs::exists(out + "/" + name));
    ++step;
  }
  // Cinema's data.csv
  {
    const InjectedFault fault(0, ENOSPC, "data.csv");
    CHECK(tessera_execute(a, step++, 0.0, &g, &f, 1) == TESSERA_ERROR_IO);
    CHECK_THAT(std::string(tessera_last_error(a)), Contains("data.csv") && Contains("No space left"));
  }
  CHECK(count_files(out, "data.csv") == 0);
  CHECK(count_files(out, ".tmp") == 0);
  // Without the fault everything is written
  CHECK(tessera_execute(a, step, 0.0, &g, &f, 1) == TESSERA_OK);
  CHECK(fs::exists(out + "/w_0003.exr"));
  CHECK(count_files(out, "data.csv") == 1);
  CHECK(tessera_close(a) == TESSERA_OK);
}

#if defined(TESSERA_RENDER_EXE) && defined(TESSERA_WRITE_DRIVER_EXE)
namespace {

/// A scene for tessera-render with its volume, output to results/ (EXR and PNG, 8x8: small
/// enough for a buffered stream to hold a whole file, the case where a final flush failed
/// unnoticed), and an 8x64 render for the adapter driver.
void write_cli_scene(const tessera_test::TempDir& dir) {
  const std::vector<float> v = to_float(blob_values(16));
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml",
            "tessera:\n  output_dir: results\n"
            "volume: {file: blob.raw, dims: [16, 16, 16], dtype: float32, spacing: [0.1, 0.1, 0.1]}\n"
            "renders:\n" +
                render_yaml("big", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr, png]}\n", "", 8, 1));
  // The driver's EXR must outgrow its effective config (~1.3 KB) for a limit between them
  std::string driver = config_yaml(
      "results",
      render_yaml("big", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr, png]}\n", "density", 8, 1));
  const std::string square = "image: {width: 8, height: 8,";
  driver.replace(driver.find(square), square.size(), "image: {width: 8, height: 64,");
  dir.write("driver.yaml", driver);
}

/// Runs `shell` (sh -c) in `dir` with a time limit; returns the exit status.
int run_shell(const tessera_test::TempDir& dir, const std::string& shell) {
  const std::string cmd = "cd '" + dir.path().string() + "' && timeout 120 sh -c '" + shell + "' > sh.out 2> sh.err";
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

/// Every regular file under `dir` (relative name -> bytes).
std::map<std::string, std::string> files_under(const std::string& dir) {
  std::map<std::string, std::string> files;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

}  // namespace

TEST_CASE("file writes: tessera-render and the adapter on a full file system fail with no file under the final name",
          "[robustness][writes][cli]") {
  tessera_test::TempDir dir;
  write_cli_scene(dir);
  // A private mount namespace with an 8 KiB tmpfs (2 pages) on results/, `fill` bytes of it
  // taken by a filler file; the listing is taken before the namespace goes away
  const auto mount = [](int fill) {
    return "mkdir -p results && unshare -m sh -c \"mount -t tmpfs -o size=8k tessera_full results || exit 97; "
           "head -c " +
           std::to_string(fill) + " /dev/zero > results/filler; ";
  };
  const std::string list = "; echo \\$? > status; ls -a results > listing\"";
  const int probe = run_shell(dir, mount(0) + "true" + list);
  if (probe != 0) {
    WARN("cannot mount a tmpfs here (needs root and unshare): full-disk test skipped; " + slurp(dir.file("sh.err")));
    return;
  }
  SECTION("tessera-render") {
    // Full: the EXR fails at its first byte
    REQUIRE(run_shell(dir, mount(8192) + "\\\"" TESSERA_RENDER_EXE "\\\" scene.yaml --quiet 2> cli.err" + list) == 0);
    CHECK(slurp(dir.file("status")) == "1\n");
    CHECK_THAT(slurp(dir.file("cli.err")),
               Contains("tessera-render: error:") && Contains("No space left on device") && Contains("big_0000.exr"));
  }
  SECTION("adapter") {
    // One page left: the effective config fits, the EXR does not
    REQUIRE(run_shell(dir, mount(4096) + "\\\"" TESSERA_WRITE_DRIVER_EXE "\\\" driver.yaml > driver.out" + list) == 0);
    CHECK(slurp(dir.file("status")) == std::to_string(int(TESSERA_ERROR_IO)) + "\n");
    CHECK_THAT(slurp(dir.file("driver.out")), Contains("execute " + std::to_string(int(TESSERA_ERROR_IO))) &&
                                                  Contains("No space left on device") && Contains("big_0000.exr"));
  }
  const std::string listing = slurp(dir.file("listing"));
  CHECK(listing.find("big_0000") == std::string::npos);
  CHECK(listing.find(".tmp") == std::string::npos);
}

TEST_CASE("file writes: under prlimit --fsize at a handful of sizes, tessera-render and the adapter leave only "
          "complete files",
          "[robustness][writes][cli]") {
  tessera_test::TempDir dir;
  write_cli_scene(dir);
  if (run_shell(dir, "command -v prlimit") != 0) {
    WARN("prlimit (util-linux) not found: test skipped");
    return;
  }
  for (const std::string program : {"tessera-render", "adapter"}) {
    DYNAMIC_SECTION(program) {
      const bool cli = program == "tessera-render";
      const std::string run = cli ? "\"" TESSERA_RENDER_EXE "\" scene.yaml --quiet --stats results/stats.json"
                                  : "\"" TESSERA_WRITE_DRIVER_EXE "\" driver.yaml";
      const int failure = cli ? 1 : int(TESSERA_ERROR_IO);
      // The complete files, without a limit
      REQUIRE(run_shell(dir, run) == 0);
      const std::map<std::string, std::string> complete = files_under(dir.file("results"));
      REQUIRE(complete.count("big_0000.exr") == 1);
      REQUIRE(complete.count("big_0000.png") == 1);
      const std::uint64_t exr = complete.at("big_0000.exr").size();
      const std::uint64_t images = std::max<std::uint64_t>(exr, complete.at("big_0000.png").size());
      std::vector<std::uint64_t> limits = {0, 1, 300, exr / 2, exr - 1};
      if (cli) {  // both images fit, the statistics (written last) do not
        REQUIRE(complete.at("stats.json").size() > images);
        limits.push_back(images);
      } else {  // the effective config fits exactly, the EXR does not
        const std::uint64_t config = complete.at("tessera_effective_config.yaml").size();
        REQUIRE(config < exr);
        limits.push_back(config);
      }
      fs::remove_all(dir.file("results"));

      for (const std::uint64_t n : limits) {
        INFO("prlimit --fsize=" << n << " (complete EXR: " << exr << " bytes)");
        // Output through a pipe: the limit applies to regular files, and the messages must get out
        REQUIRE(run_shell(dir, "(prlimit --fsize=" + std::to_string(n) + ":" + std::to_string(n) + " " + run +
                                   "; echo $? > status) 2>&1 | cat") == 0);
        CHECK(slurp(dir.file("status")) == std::to_string(failure) + "\n");
        CHECK_THAT(slurp(dir.file("sh.out")), Contains("File too large"));
        // Whatever exists is complete: byte for byte what the unlimited run wrote
        for (const auto& [name, bytes] : files_under(dir.file("results"))) {
          INFO(name);
          CHECK(name.find(".tmp") == std::string::npos);
          CHECK(name != "stats.json");  // its timings differ from run to run; never complete here
          CHECK(complete.count(name) == 1);
          CHECK((complete.count(name) == 0 || bytes == complete.at(name)));
        }
        if (n < exr) CHECK_FALSE(fs::exists(dir.file("results/big_0000.exr")));
        fs::remove_all(dir.file("results"));
      }
    }
  }
}
#endif

#ifdef TESSERA_SYNTH_EXE
TEST_CASE("file writes: tessera-synth under a file-size limit exits non-zero with no volume under its name",
          "[robustness][writes][cli]") {
  tessera_test::TempDir dir;
  const std::string synth = "\"" TESSERA_SYNTH_EXE "\" vol/v.raw --dims 8 8 8 --dtype uint8";
  // 512 bytes; with the limit one byte short the write fails
  const std::string in_dir = "cd '" + dir.path().string() + "' && ";
  REQUIRE(std::system(
              (in_dir + "(prlimit --fsize=511:511 " + synth + "; echo $? > status) 2>&1 | cat > out").c_str()) == 0);
  CHECK(slurp(dir.file("status")) != "0\n");
  CHECK_THAT(slurp(dir.file("out")), Contains("vol/v.raw") && Contains("File too large"));
  CHECK_FALSE(fs::exists(dir.file("vol/v.raw")));
  CHECK(count_files(dir.file("vol"), ".tmp") == 0);
  // Without the limit the whole file is written
  REQUIRE(std::system((in_dir + synth).c_str()) == 0);
  CHECK(fs::file_size(dir.file("vol/v.raw")) == 512);
}
#endif
