// tessera-synth end to end: --help, errors that list what is allowed, the output's folder
// created, and each kind's file size and value range (the ranges docs/cli.md documents).
#include <catch2/catch.hpp>

#include "temp_dir.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef TESSERA_SYNTH_EXE
#error "TESSERA_SYNTH_EXE must name the tessera-synth executable"
#endif

using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using tessera_test::TempDir;
namespace fs = std::filesystem;

namespace {

struct Run {
  int status;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs tessera-synth with `args` inside `dir`, capturing stdout and stderr.
Run run_synth(const TempDir& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.path().string() + "' && timeout 60 '" TESSERA_SYNTH_EXE "' " + args + " > synth.out 2> synth.err";
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir.path() / "synth.out"), slurp(dir.path() / "synth.err")};
}

/// The values of a raw file of T, widened to double.
template <class T>
std::vector<double> read_values(const fs::path& p) {
  const std::string bytes = slurp(p);
  std::vector<double> v(bytes.size() / sizeof(T));
  for (std::size_t i = 0; i < v.size(); ++i) {
    T x;
    std::memcpy(&x, bytes.data() + i * sizeof(T), sizeof(T));
    v[i] = static_cast<double>(x);
  }
  return v;
}

}  // namespace

TEST_CASE("tessera-synth --help and -h print every option and kind and exit 0", "[cli][synth]") {
  TempDir dir;
  for (const char* flag : {"--help", "-h", "out.raw --kind sphere --help"}) {
    INFO(flag);
    const Run r = run_synth(dir, flag);
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK_THAT(r.out, StartsWith("usage: tessera-synth OUT.raw"));
    for (const char* word : {"--dims", "--dtype", "--kind", "--seed", "--help", "blobs", "sphere", "linear", "float32",
                             "float64", "uint8", "int16", "uint16", "[0, 1]", "[0, 255]", "[0, 4095]", "[0, 65535]"})
      CHECK_THAT(r.out, Contains(word));
  }
  CHECK_FALSE(fs::exists(dir.path() / "out.raw"));  // --help writes nothing
}

TEST_CASE("tessera-synth errors name the problem and list what is allowed", "[cli][synth]") {
  TempDir dir;
  struct Case {
    const char* args;
    const char* message;
  };
  for (const Case& c : {
           Case{"out.raw --foo", "unknown option --foo (allowed: --dims, --dtype, --kind, --seed, -h, --help)"},
           Case{"out.raw --kind cube", "unknown kind 'cube' (allowed: blobs, sphere, linear)"},
           Case{"out.raw --dtype int8", "unknown dtype 'int8' (allowed: float32, float64, uint8, int16, uint16)"},
           Case{"out.raw --dims 4 4", "--dims needs 3 values"},
           Case{"out.raw --dims 4 0 4", "--dims: y = 0 is outside [1, 4096]"},
           Case{"out.raw --dims 4 four 4", "--dims: 'four' is not an integer"},
           Case{"out.raw --seed -3", "--seed must be in [0, 4294967295]"},
           Case{"--kind sphere", "no output file given"},
           Case{"a.raw b.raw", "two output files: 'a.raw' and 'b.raw'"},
       }) {
    INFO(c.args);
    const Run r = run_synth(dir, c.args);
    CHECK(r.status == 1);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, StartsWith("tessera-synth: error: "));
    CHECK_THAT(r.err, Contains(c.message));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one line
  }
  CHECK_FALSE(fs::exists(dir.path() / "out.raw"));
}

TEST_CASE("tessera-synth creates the output's folder", "[cli][synth]") {
  TempDir dir;
  const Run r = run_synth(dir, "data/sub/blobs.raw --dims 5 6 7 --dtype uint8");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Contains("wrote data/sub/blobs.raw: 5 x 6 x 7 uint8 (blobs)"));
  CHECK(fs::file_size(dir.path() / "data/sub/blobs.raw") == 5u * 6u * 7u);

  // A folder that cannot be created (a file is in the way) fails with a clear message.
  std::ofstream(dir.file("blocker")) << "x";
  const Run bad = run_synth(dir, "blocker/v.raw --dims 2 2 2");
  CHECK(bad.status == 1);
  CHECK_THAT(bad.err, Contains("cannot create the folder blocker"));
}

TEST_CASE("tessera-synth: each kind and dtype has the documented size and value range", "[cli][synth]") {
  TempDir dir;
  const int nx = 17, ny = 16, nz = 15;
  const std::string dims = " --dims 17 16 15";
  const std::size_t n = std::size_t(nx) * ny * nz;
  const auto minmax = [](const std::vector<double>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return std::pair{*lo, *hi};
  };

  SECTION("blobs and sphere: [0, 1] for floats, scaled for integer dtypes") {
    struct Scale {
      const char* dtype;
      std::size_t bytes;
      double max;
    };
    for (const char* kind : {"blobs", "sphere"})
      for (const Scale& s : {Scale{"float32", 4, 1.0}, Scale{"float64", 8, 1.0}, Scale{"uint8", 1, 255.0},
                             Scale{"int16", 2, 4095.0}, Scale{"uint16", 2, 65535.0}}) {
        const std::string file = std::string(kind) + "_" + s.dtype + ".raw";
        INFO(file);
        const Run r = run_synth(dir, file + dims + " --kind " + kind + " --dtype " + s.dtype);
        REQUIRE(r.status == 0);
        const fs::path p = dir.path() / file;
        CHECK(fs::file_size(p) == n * s.bytes);
        std::vector<double> v;
        if (std::string(s.dtype) == "float32") v = read_values<float>(p);
        else if (std::string(s.dtype) == "float64") v = read_values<double>(p);
        else if (std::string(s.dtype) == "uint8") v = read_values<std::uint8_t>(p);
        else if (std::string(s.dtype) == "int16") v = read_values<std::int16_t>(p);
        else v = read_values<std::uint16_t>(p);
        const auto [lo, hi] = minmax(v);
        CHECK(lo >= 0.0);
        CHECK(hi <= s.max);
        CHECK(hi > 0.5 * s.max);   // not blank: something near the top of the range
        CHECK(lo < 0.05 * s.max);  // and the corners are (near) empty
      }
  }

  SECTION("sphere: 1 at the centre voxel, 0 in the corners") {
    REQUIRE(run_synth(dir, "s.raw --dims 9 9 9 --kind sphere").status == 0);
    const std::vector<double> v = read_values<float>(dir.path() / "s.raw");
    REQUIRE(v.size() == 729u);
    CHECK(v[(4 * 9 + 4) * 9 + 4] == 1.0);
    CHECK(v[0] == 0.0);
    CHECK(v[728] == 0.0);
  }

  SECTION("linear: i + 2j + 3k, x fastest; integer dtypes clamp at their maximum") {
    REQUIRE(run_synth(dir, "l.raw" + dims + " --kind linear --dtype float64").status == 0);
    const std::vector<double> v = read_values<double>(dir.path() / "l.raw");
    REQUIRE(v.size() == n);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) REQUIRE(v[std::size_t((k * ny + j) * nx + i)] == i + 2.0 * j + 3.0 * k);
    CHECK(minmax(v).second == (nx - 1) + 2.0 * (ny - 1) + 3.0 * (nz - 1));

    REQUIRE(run_synth(dir, "l8.raw --dims 100 1 1 --kind linear --dtype uint8").status == 0);
    const std::vector<double> u = read_values<std::uint8_t>(dir.path() / "l8.raw");
    REQUIRE(u.size() == 100u);
    CHECK(u[99] == 99.0);
    REQUIRE(run_synth(dir, "l8b.raw --dims 200 60 1 --kind linear --dtype uint8").status == 0);
    CHECK(minmax(read_values<std::uint8_t>(dir.path() / "l8b.raw")).second == 255.0);
  }

  SECTION("the seed moves the blobs; the same seed gives the same bytes") {
    REQUIRE(run_synth(dir, "a.raw" + dims + " --seed 1").status == 0);
    REQUIRE(run_synth(dir, "b.raw" + dims + " --seed 1").status == 0);
    REQUIRE(run_synth(dir, "c.raw" + dims + " --seed 2").status == 0);
    CHECK(slurp(dir.path() / "a.raw") == slurp(dir.path() / "b.raw"));
    CHECK(slurp(dir.path() / "a.raw") != slurp(dir.path() / "c.raw"));
  }
}
