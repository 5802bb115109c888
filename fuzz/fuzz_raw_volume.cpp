// libFuzzer target: tessera::config::load_raw_volume, then the renderer on whatever it loads
// (scripts/fuzz.sh).
//
// Input: a 34-byte header that builds a VolumeSpec, then the bytes of the volume file (written
// to a temporary file). Header: byte 0 dtype (mod 5), byte 1 flags (bit 0 big-endian, bit 1
// "small dims": dims are bytes 2..4 + 1, else three little-endian int64 at bytes 2..25),
// bytes 26..33 header_bytes (int64; small when bit 1 is set).
// Contract under test (raw_volume.h): load_raw_volume returns a volume of exactly
// dims[0] * dims[1] * dims[2] * dtype size bytes whose view() is valid, or throws
// std::runtime_error. Loaded volumes of at most 4096 vertices are then rendered (2 x 2 pixels,
// 2 spp, single and multiple scattering) with the transfer-function range the CLI's
// `range: auto` gives them (config::resolve_range): prepare() must accept them (unless their
// finite values span more than DBL_MAX, a range prepare() refuses by name) and every pixel
// must be finite (the spec: NaN / Inf data never make a NaN pixel).
#include <tessera/config/build_scene.h>
#include <tessera/config/raw_volume.h>
#include <tessera/render.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <string>

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_raw_volume: %s: %s\n", what, detail.c_str());
  std::abort();
}

std::int64_t read_i64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

/// A temporary file for the whole run, rewritten per input.
const std::string& temp_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/tessera_fuzz_raw_XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) finding("setup", "mkstemp failed");
    close(fd);
    return tmpl;
  }();
  return path;
}

void render_volume(const tessera::config::RawVolume& vol, std::uint8_t knob) {
  const tessera::FieldView view = vol.view();
  // `range: auto`, as the CLI resolves it (config/build_scene.h)
  tessera::config::RangeSpec auto_range;
  auto_range.automatic = true;
  const auto [lo, hi] = tessera::config::resolve_range(
      auto_range, tessera::field_range(view).value_or(std::pair{0.0, 0.0}));  // none finite: as the CLI
  tessera::SceneDesc s;
  s.tf.lo = lo;
  s.tf.hi = hi;
  s.tf.density_scale = std::ldexp(1.0, (knob & 31) - 8);  // 2^-8 .. 2^23
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.tf.emission = tessera::ColorTF({0.5, 1.0}, {tessera::Color(0.0), tessera::Color(1.0)});
  const tessera::Bounds b = tessera::field_bounds(view, s.geometry);
  s.camera.look_at = b.center();
  s.camera.position = b.center() + tessera::Vec3(1.0, 0.7, -2.0) * (b.radius() + 1.0) * 2.0;
  s.lights.push_back(tessera::RectLightDesc{b.center() + tessera::Vec3(0.0, b.radius() + 1.0, 0.0), b.center(), 1.0,
                                            1.0, tessera::Color(2.0)});
  s.background.color = tessera::Color(0.3);
  s.integrator.shading = (knob & 32) ? tessera::Shading::Hybrid : tessera::Shading::Phase;
  s.integrator.scattering = (knob & 64) ? tessera::Scattering::Multiple : tessera::Scattering::Single;
  s.integrator.max_bounces = 8;
  s.integrator.macrocell = 1 + (knob >> 7) * 3;
  s.image = {2, 2, 2, 0.0};
  s.options.threads = 1;
  tessera::PreparedScene ps;
  try {
    ps = tessera::prepare(view, s);
  } catch (const std::invalid_argument& e) {
    // The one documented refusal: finite values spanning more than DBL_MAX give a range
    // whose width is not finite.
    if (!std::isfinite(hi - lo) && std::strstr(e.what(), "width")) return;
    finding("prepare() rejected a loaded volume", e.what());
  } catch (const std::exception& e) {
    finding("prepare() threw something other than std::invalid_argument", e.what());
  }
  tessera::Film film(2, 2);
  tessera::RenderStats st;
  tessera::render(ps, film, st);
  for (const float v : film.resolve().rgba)
    if (!std::isfinite(v)) finding("non-finite pixel", std::to_string(v));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kHeader = 34;
  if (size < kHeader) return 0;
  tessera::config::VolumeSpec spec;
  spec.dtype = static_cast<tessera::DType>(data[0] % 5);
  spec.byte_order = (data[1] & 1) ? tessera::config::ByteOrder::Big : tessera::config::ByteOrder::Little;
  if (data[1] & 2) {
    for (int a = 0; a < 3; ++a) spec.dims[a] = 1 + data[2 + a];
    spec.header_bytes = data[26] % 16;
  } else {
    for (int a = 0; a < 3; ++a) spec.dims[a] = read_i64(data + 2 + 8 * a);
    spec.header_bytes = read_i64(data + 26);
  }
  spec.file = temp_path();
  if (std::FILE* f = std::fopen(spec.file.c_str(), "wb")) {
    if (size > kHeader) std::fwrite(data + kHeader, 1, size - kHeader, f);
    std::fclose(f);
  } else {
    finding("setup", "cannot write " + spec.file);
  }

  tessera::config::RawVolume vol;
  try {
    vol = tessera::config::load_raw_volume(spec);
  } catch (const std::runtime_error&) {
    return 0;  // the documented way to reject a volume
  } catch (const std::exception& e) {
    finding("load_raw_volume threw something other than std::runtime_error", e.what());
  }
  // What was loaded must be exactly what the spec describes.
  const std::size_t elem = tessera::dtype_size(spec.dtype);
  long double count = 1.0L;
  for (int a = 0; a < 3; ++a) {
    if (spec.dims[a] < 1 || vol.dims[a] != spec.dims[a])
      finding("accepted dims", std::to_string(spec.dims[a]) + " on axis " + std::to_string(a));
    count *= static_cast<long double>(spec.dims[a]);
  }
  if (count * elem != static_cast<long double>(vol.bytes.size()))
    finding("size", "bytes " + std::to_string(vol.bytes.size()) + " for " + std::to_string(static_cast<double>(count)) +
                        " vertices");
  try {
    vol.view().validate("fuzzed volume");
  } catch (const std::exception& e) {
    finding("invalid view of a loaded volume", e.what());
  }
  if (count <= 4096) render_volume(vol, data[1]);
  return 0;
}
