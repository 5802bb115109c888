#pragma once
/// Shared by the in situ adapter tests: scratch directories, small configs and a test field
/// whose values are small integers (exact in every dtype), so that every memory layout and
/// dtype must render bit-identically.
#include <tessera/adapter.h>
#include <tessera/image.h>
#include <tessera/tessera.h>

#include "temp_dir.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tessera::insitu::test {

using tessera_test::TempDir;

/// One render entry (YAML, indented for `renders:`). `extra` lines go inside the entry.
inline std::string render_yaml(const std::string& name, const std::string& trigger, const std::string& extra = "",
                               const std::string& field = "density", int size = 24, int spp = 2) {
  std::string s = "  - name: " + name + "\n";
  if (!field.empty()) s += "    field: " + field + "\n";
  if (!trigger.empty()) s += "    trigger: " + trigger + "\n";
  s += "    image: {width: " + std::to_string(size) + ", height: " + std::to_string(size) +
       ", spp: " + std::to_string(spp) + "}\n";
  if (extra.find("    camera:") == std::string::npos)
    s += "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3}}, "
         "look_at: center, up: [0, 0, 1], fov: 40}\n";
  if (extra.find("    transfer_function:") == std::string::npos)
    s += "    transfer_function: {range: auto, density_scale: 40, opacity: [[0, 0], [1, 1]], "
         "diffuse: viridis}\n";
  if (extra.find("    lights:") == std::string::npos)
    s += "    lights: [{type: sphere, position: [3, -2, 3], radius: 0.4, intensity: 20}]\n";
  if (extra.find("    background:") == std::string::npos)
    s += "    background: {type: constant, color: [0.1, 0.1, 0.15]}\n";
  if (extra.find("    output:") == std::string::npos)
    s += "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
  return s + extra;
}

/// A whole config: global options (`global` lines, indented by 2) and renders.
inline std::string config_yaml(const std::string& output_dir, const std::string& renders,
                               const std::string& global = "") {
  return "tessera:\n  output_dir: " + output_dir + "\n  threads: 2\n" + global + "renders:\n" + renders;
}

/// A blob of integer values in [0, 250] on n^3 vertices, i fastest.
inline std::vector<double> blob_values(int n, double cx = 0.5) {
  std::vector<double> v(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = i / (n - 1.0) - cx, y = j / (n - 1.0) - 0.5, z = k / (n - 1.0) - 0.5;
        v[i + n * (j + static_cast<std::size_t>(n) * k)] =
            std::round(250.0 * std::exp(-(x * x + y * y + z * z) / 0.08));
      }
  return v;
}

inline std::vector<float> to_float(const std::vector<double>& v) { return std::vector<float>(v.begin(), v.end()); }

/// A dense float32 field (i fastest) named `name`.
inline tessera_field dense_field(const char* name, const float* data, int n) {
  tessera_field f{};
  f.name = name;
  f.data = data;
  f.dtype = TESSERA_FLOAT32;
  for (int a = 0; a < 3; ++a) f.dims[a] = n;
  f.byte_strides[0] = 4;
  f.byte_strides[1] = 4LL * n;
  f.byte_strides[2] = 4LL * n * n;
  return f;
}

/// The unit cube sampled by n^3 vertices, all on this rank.
inline tessera_grid unit_grid(int n) {
  tessera_grid g{};
  for (int a = 0; a < 3; ++a) {
    g.spacing[a] = 1.0 / (n - 1);
    g.global_dims[a] = n;
  }
  return g;
}

inline bool same_pixels(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

inline double mean_luminance(const Image& img) {
  double s = 0.0;
  for (std::size_t p = 0; p < img.rgba.size(); p += 4)
    s += 0.2126 * img.rgba[p] + 0.7152 * img.rgba[p + 1] + 0.0722 * img.rgba[p + 2];
  return s / (img.rgba.size() / 4);
}

}  // namespace tessera::insitu::test
