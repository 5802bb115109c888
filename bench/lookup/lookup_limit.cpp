// lookup_limit: how many field lookups per second one core can do at best, for the operation
// the renderer repeats most: a trilinear lookup of a scalar volume plus a transfer-function
// opacity lookup, at exponentially distributed steps along coherent rays (free-flight /
// delta tracking against a constant majorant). It is the ceiling beside which the renderer's
// achieved lookups per second (bench/perf/perf.py, "lookups/s") is read.
//
//   lookup_limit [--raw FILE NX NY NZ int16|float32] [--grid N] [--rays R] [--reps K]
//                [--ramp LO HI] [--csv FILE]
// --ramp: where the opacity ramps up, as fractions of the value range (default 0.75 0.9; the
// invesalius head CT of scripts/fetch_ct.sh: 0.4 0.55, about 600 to 1200 HU).
//
// Variants, each over the same rays, steps and volume:
//   scalar-double  one ray at a time, double coordinates and interpolation (as the kernel today)
//   scalar-float   one ray at a time, float throughout
//   interleaved4-double  4 rays in scalar double, advanced a step each in turn (a scalar
//                  wavefront: whether overlapping rays' dependent chains pays without SIMD)
//   simd8-float    8 rays at a time (GCC vector extensions; AVX2 gathers when the CPU has them),
//                  with a vector logarithm for the exponential steps
// Prints lookups/s per core and the checksum of each (the sums must agree to float precision).
#include "lookup_kernels.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace lookup_bench;

namespace {

struct Args {
  std::string raw, raw_dtype = "int16", csv;
  int dims[3] = {0, 0, 0};
  int grid = 256, rays = 1 << 14, reps = 3;
  float ramp_lo = 0.75f, ramp_hi = 0.9f;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto need = [&](int n) {
      if (i + n >= argc) {
        std::fprintf(stderr, "%s needs %d value(s)\n", s.c_str(), n);
        std::exit(2);
      }
    };
    if (s == "--raw") {
      need(5);
      a.raw = argv[++i];
      for (int& d : a.dims) d = std::atoi(argv[++i]);
      a.raw_dtype = argv[++i];
    } else if (s == "--grid") {
      need(1);
      a.grid = std::atoi(argv[++i]);
    } else if (s == "--rays") {
      need(1);
      a.rays = std::atoi(argv[++i]);
    } else if (s == "--reps") {
      need(1);
      a.reps = std::atoi(argv[++i]);
    } else if (s == "--ramp") {
      need(2);
      a.ramp_lo = float(std::atof(argv[++i]));
      a.ramp_hi = float(std::atof(argv[++i]));
    } else if (s == "--csv") {
      need(1);
      a.csv = argv[++i];
    } else {
      std::fprintf(stderr, "unknown argument %s\n", s.c_str());
      std::exit(2);
    }
  }
  if (a.grid < 4 || a.grid > 1024 || a.rays < 8 || a.reps < 1 ||
      !(0 <= a.ramp_lo && a.ramp_lo < a.ramp_hi && a.ramp_hi <= 1)) {
    std::fprintf(stderr, "need --grid in [4, 1024], --rays >= 8, --reps >= 1, 0 <= ramp LO < HI <= 1\n");
    std::exit(2);
  }
  return a;
}

/// The volume as float32 (the CT converted once; the bench measures lookups, not conversion)
Volume load(const Args& a) {
  Volume v;
  if (a.raw.empty()) {
    v = synthetic_volume(a.grid);
    v.name = "synthetic " + std::to_string(a.grid) + "^3";
    return v;
  }
  for (int d : a.dims)
    if (d < 2) throw std::runtime_error("--raw: dims must be >= 2");
  const std::size_t n = std::size_t(a.dims[0]) * a.dims[1] * a.dims[2];
  std::ifstream in(a.raw, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + a.raw);
  v.nx = a.dims[0];
  v.ny = a.dims[1];
  v.nz = a.dims[2];
  v.data.resize(n);
  if (a.raw_dtype == "int16") {
    std::vector<std::int16_t> raw(n);
    if (!in.read(reinterpret_cast<char*>(raw.data()), std::streamsize(n * 2))) throw std::runtime_error("short file");
    for (std::size_t i = 0; i < n; ++i) v.data[i] = raw[i];
  } else if (a.raw_dtype == "float32") {
    if (!in.read(reinterpret_cast<char*>(v.data.data()), std::streamsize(n * 4)))
      throw std::runtime_error("short file");
  } else {
    throw std::runtime_error("--raw dtype must be int16 or float32");
  }
  v.name = a.raw;
  return v;
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a = parse(argc, argv);
  const Volume vol = load(a);
  const Setup setup = make_setup(vol, a.rays, a.ramp_lo, a.ramp_hi);
  std::printf("lookup_limit: %s, %d rays, majorant %.4g per voxel, TF range [%g, %g], %s\n", vol.name.c_str(), a.rays,
              setup.majorant, setup.tf_lo, setup.tf_hi, simd_gathers() ? "AVX2 gathers" : "no AVX2: scalar gathers");
  std::FILE* csv = a.csv.empty() ? nullptr : std::fopen(a.csv.c_str(), "w");
  if (csv) std::fprintf(csv, "variant,lookups,seconds,lookups_per_s,checksum\n");
  for (Variant var : {Variant::ScalarDouble, Variant::ScalarFloat, Variant::Interleaved4Double, Variant::Simd8Float}) {
    double best = 1e300;
    Result r{};
    for (int rep = 0; rep < a.reps; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      r = run(var, vol, setup);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (s < best) best = s;
    }
    const double rate = double(r.lookups) / best;
    std::printf("  %-20s %12llu lookups  %8.3f s  %7.2f M lookups/s per core  checksum %.6g\n", variant_name(var),
                static_cast<unsigned long long>(r.lookups), best, rate * 1e-6, r.checksum);
    if (csv)
      std::fprintf(csv, "%s,%llu,%.6f,%.6g,%.9g\n", variant_name(var), static_cast<unsigned long long>(r.lookups), best,
                   rate, r.checksum);
  }
  if (csv) std::fclose(csv);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "lookup_limit: %s\n", e.what());
  return 1;
}
