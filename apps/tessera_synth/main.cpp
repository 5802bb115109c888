/// tessera-synth: writes a synthetic raw volume, so demos and benchmarks need no download.
///
///   tessera-synth OUT.raw [--dims NX NY NZ] [--dtype float32|float64|uint8|int16|uint16]
///                         [--kind blobs|sphere|linear] [--seed N]
///
/// blobs:  a shell plus Gaussian blobs with a little value noise, values in [0, 1] (scaled to
///         the integer range for integer dtypes);  sphere: 1 - r (radial ramp);
/// linear: v = x + 2y + 3z in voxel units (for interpolation checks).
#include <tessera/field_view.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Args {
  std::string out;
  std::int64_t dims[3] = {128, 128, 128};
  std::string dtype = "float32";
  std::string kind = "blobs";
  unsigned seed = 7;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto need = [&](int n) {
      if (i + n >= argc) throw std::runtime_error(s + " needs " + std::to_string(n) + " value(s)");
    };
    if (s == "--dims") {
      need(3);
      for (int k = 0; k < 3; ++k) a.dims[k] = std::stoll(argv[++i]);
    } else if (s == "--dtype") {
      need(1);
      a.dtype = argv[++i];
    } else if (s == "--kind") {
      need(1);
      a.kind = argv[++i];
    } else if (s == "--seed") {
      need(1);
      a.seed = static_cast<unsigned>(std::stoul(argv[++i]));
    } else if (!s.empty() && s[0] == '-') {
      throw std::runtime_error("unknown option " + s);
    } else {
      a.out = s;
    }
  }
  if (a.out.empty()) throw std::runtime_error("usage: tessera-synth OUT.raw [--dims NX NY NZ] [--dtype T] [--kind blobs|sphere|linear]");
  for (auto d : a.dims)
    if (d < 1 || d > 4096) throw std::runtime_error("dims must be in [1, 4096]");
  return a;
}

template <class T>
void write_as(const Args& a, const std::vector<double>& v, double scale) {
  std::vector<T> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = static_cast<T>(v[i] * scale);
  std::ofstream f(a.out, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + a.out);
  f.write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size() * sizeof(T)));
  if (!f) throw std::runtime_error("write failed: " + a.out);
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a = parse(argc, argv);
  const std::int64_t nx = a.dims[0], ny = a.dims[1], nz = a.dims[2];
  std::vector<double> v(static_cast<std::size_t>(nx * ny * nz));
  std::mt19937 rng(a.seed);
  std::uniform_real_distribution<double> U(0.2, 0.8);
  struct Blob { double x, y, z, r, w; };
  std::vector<Blob> blobs;
  for (int b = 0; b < 7; ++b) blobs.push_back({U(rng), U(rng), U(rng), 0.05 + 0.1 * U(rng), 0.5 + U(rng) * 0.6});
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        const double x = nx > 1 ? double(i) / (nx - 1) : 0.5, y = ny > 1 ? double(j) / (ny - 1) : 0.5,
                     z = nz > 1 ? double(k) / (nz - 1) : 0.5;
        const double r = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
        double val = 0.0;
        if (a.kind == "sphere") {
          val = std::fmax(0.0, 1.0 - 2.0 * r);
        } else if (a.kind == "linear") {
          val = double(i) + 2.0 * j + 3.0 * k;
        } else if (a.kind == "blobs") {
          val = 0.45 * std::exp(-std::pow((r - 0.42) / 0.025, 2.0));  // thin shell
          for (const Blob& b : blobs) {
            const double d2 = (x - b.x) * (x - b.x) + (y - b.y) * (y - b.y) + (z - b.z) * (z - b.z);
            val += b.w * std::exp(-d2 / (b.r * b.r));
          }
          val += 0.04 * std::sin(23.0 * x) * std::sin(19.0 * y) * std::sin(29.0 * z);
          val = std::fmin(1.0, std::fmax(0.0, val));
        } else {
          throw std::runtime_error("unknown kind " + a.kind + " (blobs, sphere, linear)");
        }
        v[static_cast<std::size_t>((k * ny + j) * nx + i)] = val;
      }
  if (a.dtype == "float32") write_as<float>(a, v, 1.0);
  else if (a.dtype == "float64") write_as<double>(a, v, 1.0);
  else if (a.dtype == "uint8") write_as<std::uint8_t>(a, v, a.kind == "linear" ? 1.0 : 255.0);
  else if (a.dtype == "int16") write_as<std::int16_t>(a, v, a.kind == "linear" ? 1.0 : 4095.0);
  else if (a.dtype == "uint16") write_as<std::uint16_t>(a, v, a.kind == "linear" ? 1.0 : 65535.0);
  else throw std::runtime_error("unknown dtype " + a.dtype);
  std::printf("wrote %s: %lld x %lld x %lld %s (%s)\n", a.out.c_str(), (long long)nx, (long long)ny,
              (long long)nz, a.dtype.c_str(), a.kind.c_str());
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "tessera-synth: error: %s\n", e.what());
  return 1;
}
