// Robustness tests: see CMakeLists.txt in this folder.
// Loading cost and file types (docs/config.md "Limits"): config loading is linear in the file
// size and bounded (file size limit, hash-based duplicate keys, a node budget for aliases, one
// document), every file key refuses non-regular files without blocking, and an EXR header
// cannot decide an allocation its file could not hold.
#include <tessera/config/config.h>
#include <tessera/config/raw_volume.h>
#include <tessera/image_io.h>
#include <tessera/regular_file.h>

#include <catch2/catch.hpp>

#include "loading_support.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <future>
#include <string>

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using tessera_test::TempDir;
using namespace tessera_test::loading;
using Clock = std::chrono::steady_clock;

namespace {

/// A mapping of `n` distinct keys under `tessera:` (15 bytes a key), then `tail`.
std::string big_mapping(std::size_t n, const std::string& tail) {
  std::string s = "tessera:\n";
  s.reserve(n * 18 + tail.size() + 16);
  for (std::size_t i = 0; i < n; ++i) s += "  k" + std::to_string(10'000'000 + i) + ": 1\n";
  return s + tail;
}

/// Billion laughs through accepted structure: `renders` distinct renders that all share one
/// trigger whose `at:` list holds `steps` aliases of one step (file ~ 4 * (steps + 16 renders)
/// bytes, walk ~ renders * steps nodes).
std::string alias_bomb(int renders, int steps) {
  std::string s = "renders:\n  - {name: r0, camera: &c {position: [0, 0, 5]}, "
                  "transfer_function: &t {opacity: [[0, 1]]}, trigger: &g {at: [&q 1";
  for (int i = 1; i < steps; ++i) s += ", *q";
  s += "]}}\n";
  for (int i = 1; i < renders; ++i)
    s += "  - {name: r" + std::to_string(i) + ", camera: *c, transfer_function: *t, trigger: *g}\n";
  return s;
}

/// Runs `f` on another thread; if it has not returned after `seconds`, opens `fifo` for
/// writing (which releases a reader blocked on it) and reports false.
template <class F>
bool returns_within(double seconds, const std::string& fifo, F&& f) {
  auto done = std::async(std::launch::async, std::forward<F>(f));
  if (done.wait_for(std::chrono::duration<double>(seconds)) == std::future_status::ready) {
    done.get();
    return true;
  }
  const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
  if (fd >= 0) ::close(fd);
  done.wait();
  return false;
}

/// A valid 4x2 EXR written by write_exr, then its data window patched to (0,0)-(x1,y1).
std::string exr_with_window(const TempDir& dir, const std::string& name, int x1, int y1) {
  tessera::Image img;
  img.width = 4;
  img.height = 2;
  img.rgba.assign(4 * 2 * 4, 0.5f);
  const std::string path = dir.file(name);
  tessera::write_exr(path, img);
  std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::string tag("dataWindow\0box2i\0", 17);
  const std::size_t at = bytes.find(tag);
  REQUIRE(at != std::string::npos);
  const std::size_t box = at + tag.size() + 4;    // after the int32 size (16)
  const std::int32_t window[4] = {0, 0, x1, y1};  // little endian on the machines we test
  f.seekp(static_cast<std::streamoff>(box));
  f.write(reinterpret_cast<const char*>(window), sizeof window);
  return path;
}

}  // namespace

TEST_CASE("a config over the size limit fails before it is read", "[robustness][loading]") {
  TempDir dir;
  const std::string path = dir.write("big.yaml", big_mapping(700'000, "renders:\n" + minimal_render()));
  REQUIRE(std::filesystem::file_size(path) > 10'000'000);
  const auto t0 = Clock::now();
  const std::string e = load_error(path);
  CHECK(seconds_since(t0) < 20.0);
  CHECK_THAT(e, Contains("big.yaml: config is "));
  CHECK_THAT(e, Contains("allowed: at most 4194304 bytes"));
  // The same text given directly (C API, parse_config)
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK_THAT(config_error(text), Contains("allowed: at most 4194304 bytes"));
}

TEST_CASE("a large mapping loads in linear time and its duplicate key is found", "[robustness][loading]") {
  // 150,000 keys (~2.7 MB): quadratic checking took minutes at this size
  std::string yaml = big_mapping(150'000, "");
  yaml += "  k10000007: 2\n";  // the duplicate, after all the others
  const auto t0 = Clock::now();
  const std::string e = config_error(yaml);
  CHECK(seconds_since(t0) < 20.0);
  CHECK_THAT(e, StartsWith("scene.yaml:150002:3: tessera.k10000007: duplicate key (first given at "
                           "line 9)"));

  // Without the duplicate: the first unknown key is reported, just as fast
  const std::string e2 = config_error(big_mapping(150'000, ""));
  CHECK_THAT(e2, StartsWith("scene.yaml:2:3: tessera.k10000000: unknown key"));
}

TEST_CASE("an alias bomb fails on the node budget with a location", "[robustness][loading]") {
  // ~2.3 MB that expands to 30,000 x 40,000 step values
  const std::string yaml = alias_bomb(30'000, 40'000);
  const auto t0 = Clock::now();
  const std::string e = config_error(yaml);
  CHECK(seconds_since(t0) < 20.0);
  CHECK_THAT(e, Contains("renders["));
  CHECK_THAT(e, Contains("].trigger.at: the config expands to more than"));
  CHECK_THAT(e, StartsWith("scene.yaml:2:"));  // where the shared list is, line 2

  // A config that uses an alias a few times is fine
  const std::string small = alias_bomb(3, 10);
  CHECK(config_error(small) == "");
}

TEST_CASE("a file without aliases never reaches the node budget", "[robustness][loading]") {
  // 1.2 million steps written out, two bytes each: above the 1,000,000 base, under half the
  // file size
  std::string yaml = "renders:\n" + minimal_render() + "    trigger: {at: [";
  yaml.reserve(yaml.size() + 2'400'100);
  for (int i = 0; i < 1'200'000; ++i) yaml += "1,";
  yaml += "1]}\n";
  const auto t0 = Clock::now();
  CHECK(config_error(yaml) == "");
  CHECK(seconds_since(t0) < 20.0);
}

#ifdef TESSERA_RENDER_EXE
TEST_CASE("the alias bomb fails with bounded memory through the CLI", "[robustness][loading]") {
  TempDir dir;
  dir.write("bomb.yaml", alias_bomb(30'000, 60'000));
  // 1 GB of address space: without the budget the walk needs many GB. AddressSanitizer
  // reserves terabytes of shadow memory, so there the budget is checked without the cap.
#if defined(__SANITIZE_ADDRESS__)
  const Run r = run_cli(dir, "bomb.yaml", "", 60);
#else
  const Run r = run_cli(dir, "bomb.yaml", "ulimit -v 1000000;", 60);
#endif
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("bomb.yaml:2:"));
  CHECK_THAT(r.err, Contains("the config expands to more than"));
}
#endif

TEST_CASE("deep nesting fails cleanly", "[robustness][loading]") {
  const std::string lists = "renders: " + std::string(200'000, '[') + std::string(200'000, ']');
  CHECK_THAT(config_error(lists), StartsWith("scene.yaml:1:") && Contains("nested too deeply"));
  std::string maps = "renders: ";
  for (int i = 0; i < 100'000; ++i) maps += "{a: ";
  maps += "1" + std::string(100'000, '}');
  CHECK_THAT(config_error(maps), Contains("nested too deeply"));
}

TEST_CASE("input on which yaml-cpp's LoadAll never ends is refused at once", "[robustness][loading]") {
  // YAML::LoadAll(",") returns documents without end until memory runs out (fuzz finding);
  // documents are therefore counted with yaml-cpp's event parser, two at most
  for (const char* text : {",", "---\n,", "renders: []\n---\n,\n---\n,"}) {
    INFO(text);
    const auto t0 = Clock::now();
    CHECK(config_error(text) != "");
    CHECK(seconds_since(t0) < 20.0);
  }
}

TEST_CASE("a second YAML document is an error naming its line", "[robustness][loading]") {
  const std::string one = "renders:\n" + minimal_render();
  CHECK(config_error(one) == "");
  // An empty second document is harmless
  CHECK(config_error(one + "---\n") == "");
  CHECK(config_error("---\n" + one + "...\n") == "");
  const std::string e = config_error(one + "---\nrenders:\n" + minimal_render("b"));
  CHECK_THAT(e, StartsWith("scene.yaml:7:1: a second YAML document starts here"));
}

TEST_CASE("non-regular files are refused for every file key, without blocking", "[robustness][loading]") {
  TempDir dir;
  const std::string fifo = dir.file("pipe");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string vol = volume_block(dir);
  const std::string render = minimal_render();

  SECTION("envmap") {
    const std::string yaml = vol + "renders:\n" + render + "    background: {type: envmap, file: pipe}\n";
    std::string e;
    CHECK(returns_within(10.0, fifo, [&] { e = config_error(yaml, dir.path().string()); }));
    CHECK_THAT(e, StartsWith("scene.yaml:7:32: renders[0].background.file: "));
    CHECK_THAT(e, Contains("pipe is a FIFO (allowed: a regular file)"));
    // The core reader itself, as the adapter and the CLI reach it
    std::string e2;
    CHECK(returns_within(10.0, fifo, [&] {
      try {
        tessera::read_exr(fifo);
      } catch (const std::exception& ex) {
        e2 = ex.what();
      }
    }));
    CHECK_THAT(e2, Contains("is a FIFO (allowed: a regular file)"));
  }
  SECTION("volume file") {
    const std::string yaml = "volume: {file: pipe, dims: [2, 2, 2], dtype: float32}\nrenders:\n" + render;
    std::string e;
    CHECK(returns_within(10.0, fifo, [&] { e = config_error(yaml, dir.path().string()); }));
    CHECK_THAT(e, StartsWith("scene.yaml:1:10: volume.file: "));
    CHECK_THAT(e, Contains("is a FIFO (allowed: a regular file)"));
    tessera::config::VolumeSpec spec;
    spec.file = fifo;
    spec.dims[0] = spec.dims[1] = spec.dims[2] = 2;
    std::string e2;
    CHECK(returns_within(10.0, fifo, [&] {
      try {
        tessera::config::load_raw_volume(spec);
      } catch (const std::exception& ex) {
        e2 = ex.what();
      }
    }));
    CHECK_THAT(e2, Contains("is a FIFO (allowed: a regular file)"));
  }
  SECTION("the config file itself") {
    std::string e;
    CHECK(returns_within(10.0, fifo, [&] { e = load_error(fifo); }));
    CHECK_THAT(e, Contains("is a FIFO (allowed: a regular file)"));
  }
  SECTION("devices and directories") {
    const std::string yaml = "volume: {file: /dev/zero, dims: [2, 2, 2], dtype: float32}\n"
                             "renders:\n" +
                             render;
    CHECK_THAT(config_error(yaml), Contains("/dev/zero is a character device (allowed: a regular file)"));
    CHECK_THAT(
        config_error(vol + "renders:\n" + render + "    background: {type: envmap, file: .}\n", dir.path().string()),
        Contains("is a directory"));
    CHECK_THAT(load_error("/dev/zero"), Contains("is a character device"));
  }
}

TEST_CASE("an EXR header cannot ask for more than its file holds", "[robustness][loading]") {
  TempDir dir;
  // Sanity: the unpatched file reads
  const std::string ok = exr_with_window(dir, "ok.exr", 3, 1);
  CHECK(tessera::read_exr(ok).width == 4);
  CHECK(tessera::read_exr_size(ok).width == 4);
  CHECK(tessera::read_exr_size(ok).height == 2);

  const auto error_of = [](const std::string& path) {
    try {
      tessera::read_exr(path);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // Over the documented maximum: refused from the header, before any allocation
  const std::string huge = exr_with_window(dir, "huge.exr", 99'999, 99'999);
  CHECK_THAT(error_of(huge), Contains("huge.exr") && Contains("data window 100000x100000 is too large"));
  CHECK_THROWS_WITH(tessera::read_exr_size(huge), Contains("is too large"));
  const std::string wide = exr_with_window(dir, "wide.exr", 16'384, 0);
  CHECK_THAT(error_of(wide), Contains("data window 16385x1 is too large"));
  // Under the maximum but far more than a file of a few hundred bytes can hold
  const std::string big = exr_with_window(dir, "big.exr", 8191, 8191);
  CHECK_THAT(error_of(big), Contains("data window 8192x8192 needs 1073741824 bytes of pixels") &&
                                Contains("at most 1100 times the file size"));
  // Few pixels but more chunks than the file has room for in its offset table
  const std::string tall = exr_with_window(dir, "tall.exr", 0, 16383);
  CHECK_THAT(error_of(tall), Contains("data window 1x16384 needs 1024 chunks"));
  // Garbage and truncated headers fail cleanly
  dir.write("junk.exr", "not an exr file at all");
  CHECK_THAT(error_of(dir.file("junk.exr")), Contains("not an OpenEXR file"));
  std::ifstream in(ok, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  dir.write("cut.exr", bytes.substr(0, 40));
  CHECK_THAT(error_of(dir.file("cut.exr")), Contains("cut.exr"));
  dir.write("tail.exr", bytes.substr(0, bytes.size() - 20));
  CHECK_THAT(error_of(dir.file("tail.exr")), Contains("tail.exr"));
}

TEST_CASE("spp above the maximum is refused at load and on the command line", "[robustness][loading]") {
  const std::string e = config_error("renders:\n  - name: a\n    image: {spp: 2147483647}\n");
  CHECK_THAT(e, StartsWith("scene.yaml:3:13: renders[0].image.spp: 2147483647 is out of range "
                           "[1, 1048576]"));
  CHECK(config_error("renders:\n" +
                     std::string(minimal_render()).replace(minimal_render().find("spp: 1"), 6, "spp: 1048576")) == "");
#ifdef TESSERA_RENDER_EXE
  TempDir dir;
  dir.write("scene.yaml", volume_block(dir) + "renders:\n" + minimal_render());
  const Run r = run_cli(dir, "scene.yaml --spp 2147483647", "", 60);
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("--spp: \"2147483647\" is not an integer in [1, 1048576]"));
  const Run w = run_cli(dir, "scene.yaml --width 16385", "", 60);
  CHECK(w.status == 1);
  CHECK_THAT(w.err, Contains("--width: \"16385\" is not an integer in [1, 16384]"));
#endif
}

TEST_CASE("control characters in output.file are refused at load", "[robustness][loading]") {
  const std::string head = "renders:\n" + minimal_render() + "    output: {file: ";
  CHECK_THAT(config_error(head + "\"a\\0b\"}\n"),
             StartsWith("scene.yaml:6:14: renders[0].output.file: bad output pattern \"a\\x00b\": "
                        "control character \\x00 at position 2"));
  CHECK_THAT(config_error(head + "\"a\\nb\"}\n"), Contains("control character \\x0a"));
  CHECK_THAT(config_error(head + "\"dir/\"}\n"), Contains("the file name is empty"));
  CHECK_THAT(config_error("tessera: {output_dir: \"out\\0x\"}\nrenders:\n" + minimal_render()),
             StartsWith("scene.yaml:1:11: tessera.output_dir: ") && Contains("control character"));
  // The writers refuse a NUL in a path whatever the caller
  tessera::Image img;
  img.width = img.height = 1;
  img.rgba.assign(4, 1.0f);
  CHECK_THROWS_WITH(tessera::write_exr(std::string("a\0b.exr", 7), img), Contains("NUL"));
  CHECK_THROWS_WITH(tessera::write_png(std::string("a\0b.png", 7), img), Contains("NUL"));
}

TEST_CASE("Cinema views are bounded: each one is a whole render", "[robustness][loading]") {
  std::string az, el;
  for (int i = 0; i < 100; ++i) az += (i ? ", " : "") + std::to_string(i * 3.6);
  for (int i = 0; i < 41; ++i) el += (i ? ", " : "") + std::to_string(-80 + 4 * i);
  const std::string head =
      "renders:\n" + minimal_render() + "    output: {cinema: {azimuth: [" + az + "], elevation: [";
  CHECK_THAT(config_error(head + el + "]}}\n"),
             Contains("renders[0].output.cinema: 100 azimuths x 41 elevations make 4100 views (allowed: at most "
                      "4096 views per render)"));
  CHECK(config_error(head + "0, 30, 60]}}\n") == "");
}
