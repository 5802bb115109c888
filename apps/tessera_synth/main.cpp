/// tessera-synth: writes a synthetic raw volume, so demos and benchmarks need no download.
///
///   tessera-synth OUT.raw [--dims NX NY NZ] [--dtype float32|float64|uint8|int16|uint16]
///                         [--kind blobs|sphere|linear] [--seed N]     (--help: usage, exit 0)
///
/// Values (x fastest, then y, then z; native byte order); usage() lists them with their
/// ranges, docs/cli.md "tessera-synth" documents them:
/// blobs:  a shell plus Gaussian blobs with a little value noise, values in [0, 1] (scaled to
///         255 / 4095 / 65535 for uint8 / int16 / uint16);  sphere: max(0, 1 - 2r), r the
///         distance from the centre in units of the box (1 at the centre, 0 from r = 0.5);
/// linear: v = i + 2j + 3k in voxel indices (for interpolation checks), unscaled (integer
///         dtypes clamp at their maximum). Integer dtypes truncate toward zero.
/// The output's folder is created when missing.
#include <tessera/atomic_output.h>
#include <tessera/field_view.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <new>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace {

struct Args {
  std::string out;
  std::int64_t dims[3] = {128, 128, 128};
  std::string dtype = "float32";
  std::string kind = "blobs";
  unsigned seed = 7;
  bool help = false;
};

const char* usage() {
  return R"(usage: tessera-synth OUT.raw [--dims NX NY NZ] [--dtype T] [--kind K] [--seed N]

Writes a synthetic raw volume (x fastest, then y, then z; native byte order) of
NX*NY*NZ values of type T to OUT.raw, creating its folder when missing.

options:
  --dims NX NY NZ  voxels per axis, each in [1, 4096] (default 128 128 128)
  --dtype T        float32 (default), float64, uint8, int16, uint16
  --kind K         blobs (default), sphere, linear (below)
  --seed N         seed of the blob positions (default 7; only blobs uses it)
  -h, --help       print this help and exit

kinds and the values they produce:
  blobs   a thin shell plus 7 Gaussian blobs and a little value noise, in [0, 1]
          (float32/float64); integer dtypes scale it: uint8 [0, 255], int16 [0, 4095],
          uint16 [0, 65535]
  sphere  max(0, 1 - 2r), r the distance from the centre in units of the box: in [0, 1],
          1 at the centre, 0 from r = 0.5 out; scaled like blobs for integer dtypes
  linear  i + 2j + 3k in voxel indices, in [0, (NX-1) + 2(NY-1) + 3(NZ-1)], not scaled
          (for interpolation checks; integer dtypes clamp at their maximum)

example:
  tessera-synth data/blobs.raw --dims 128 128 128 --kind blobs
)";
}

constexpr const char* kOptions = "--dims, --dtype, --kind, --seed, -h, --help";
constexpr const char* kKinds = "blobs, sphere, linear";
constexpr const char* kDtypes = "float32, float64, uint8, int16, uint16";

/// std::stoll / stoul with an error that names the option and the bad value.
long long to_integer(const std::string& opt, const std::string& v) {
  std::size_t used = 0;
  long long n = 0;
  try {
    n = std::stoll(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size()) throw std::runtime_error(opt + ": '" + v + "' is not an integer");
  return n;
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto need = [&](int n) {
      if (i + n >= argc) throw std::runtime_error(s + " needs " + std::to_string(n) + (n == 1 ? " value" : " values"));
    };
    if (s == "-h" || s == "--help") {
      a.help = true;
      return a;
    } else if (s == "--dims") {
      need(3);
      for (int k = 0; k < 3; ++k) a.dims[k] = to_integer(s, argv[++i]);
    } else if (s == "--dtype") {
      need(1);
      a.dtype = argv[++i];
    } else if (s == "--kind") {
      need(1);
      a.kind = argv[++i];
    } else if (s == "--seed") {
      need(1);
      const long long seed = to_integer(s, argv[++i]);
      if (seed < 0 || seed > 4294967295LL) throw std::runtime_error("--seed must be in [0, 4294967295]");
      a.seed = static_cast<unsigned>(seed);
    } else if (s.size() > 1 && s[0] == '-') {
      throw std::runtime_error("unknown option " + s + " (allowed: " + kOptions + ")");
    } else if (!a.out.empty()) {
      throw std::runtime_error("two output files: '" + a.out + "' and '" + s + "' (one OUT.raw is allowed)");
    } else {
      a.out = s;
    }
  }
  if (a.out.empty())
    throw std::runtime_error("no output file given (usage: tessera-synth OUT.raw [options]; --help lists them)");
  const char* axis = "xyz";
  for (int k = 0; k < 3; ++k)
    if (a.dims[k] < 1 || a.dims[k] > 4096)
      throw std::runtime_error(std::string("--dims: ") + axis[k] + " = " + std::to_string(a.dims[k]) +
                               " is outside [1, 4096]");
  if (a.kind != "blobs" && a.kind != "sphere" && a.kind != "linear")
    throw std::runtime_error("unknown kind '" + a.kind + "' (allowed: " + kKinds + ")");
  if (a.dtype != "float32" && a.dtype != "float64" && a.dtype != "uint8" && a.dtype != "int16" && a.dtype != "uint16")
    throw std::runtime_error("unknown dtype '" + a.dtype + "' (allowed: " + kDtypes + ")");
  return a;
}

template <class T>
void write_as(const Args& a, const std::vector<double>& v, double scale) {
  std::vector<T> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    double x = v[i] * scale;
    if constexpr (std::is_integral_v<T>)  // clamp: an out-of-range conversion is undefined
      x = std::fmin(std::fmax(std::trunc(x), double(std::numeric_limits<T>::min())),
                    double(std::numeric_limits<T>::max()));
    out[i] = static_cast<T>(x);
  }
  const std::filesystem::path parent = std::filesystem::path(a.out).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec) throw std::runtime_error("cannot create the folder " + parent.string() + ": " + ec.message());
  tessera::write_file_atomically(a.out,
                                 std::string_view(reinterpret_cast<const char*>(out.data()), out.size() * sizeof(T)));
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a = parse(argc, argv);
  if (a.help) {
    std::fputs(usage(), stdout);
    return 0;
  }
  const std::int64_t nx = a.dims[0], ny = a.dims[1], nz = a.dims[2];
  std::vector<double> v(static_cast<std::size_t>(nx * ny * nz));
  std::mt19937 rng(a.seed);
  std::uniform_real_distribution<double> U(0.2, 0.8);
  struct Blob {
    double x, y, z, r, w;
  };
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
          throw std::runtime_error("unknown kind '" + a.kind + "' (allowed: " + kKinds + ")");
        }
        v[static_cast<std::size_t>((k * ny + j) * nx + i)] = val;
      }
  if (a.dtype == "float32") write_as<float>(a, v, 1.0);
  else if (a.dtype == "float64") write_as<double>(a, v, 1.0);
  else if (a.dtype == "uint8") write_as<std::uint8_t>(a, v, a.kind == "linear" ? 1.0 : 255.0);
  else if (a.dtype == "int16") write_as<std::int16_t>(a, v, a.kind == "linear" ? 1.0 : 4095.0);
  else if (a.dtype == "uint16") write_as<std::uint16_t>(a, v, a.kind == "linear" ? 1.0 : 65535.0);
  else throw std::runtime_error("unknown dtype '" + a.dtype + "' (allowed: " + kDtypes + ")");
  std::printf("wrote %s: %lld x %lld x %lld %s (%s)\n", a.out.c_str(), (long long)nx, (long long)ny, (long long)nz,
              a.dtype.c_str(), a.kind.c_str());
  return 0;
} catch (const std::bad_alloc&) {
  std::fprintf(
      stderr, "tessera-synth: error: out of memory (it holds 8 bytes per voxel plus the output; try smaller --dims)\n");
  return 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "tessera-synth: error: %s\n", e.what());
  return 1;
}
