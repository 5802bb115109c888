#pragma once
/// Shared by test_denoise.cpp and test_open_paths.cpp: a small CLI scene with image.denoise.
/// Test code only.
#include "../insitu/insitu_test_support.h"

#include <fstream>
#include <string>
#include <vector>

namespace tessera_test::denoise {

/// `image: {..., spp: N}` of render_yaml with `denoise: <on>` added.
inline std::string with_denoise(std::string render, bool on) {
  const std::size_t p = render.find("}\n", render.find("image:"));
  return render.insert(p, std::string(", denoise: ") + (on ? "true" : "false"));
}

/// A 16^3 float32 blob and a CLI scene with one `size`^2 render writing EXR and PNG.
inline void write_cli_scene(const TempDir& dir, bool denoise, int size = 32) {
  using namespace tessera::insitu::test;
  const std::vector<float> v = to_float(blob_values(16));
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml",
            "tessera:\n  output_dir: results\n"
            "volume: {file: blob.raw, dims: [16, 16, 16], dtype: float32, spacing: [0.1, 0.1, 0.1]}\n"
            "renders:\n" +
                with_denoise(render_yaml("d", "", "    output: {file: \"{name}\", formats: [exr, png]}\n", "", size, 4),
                             denoise));
}

}  // namespace tessera_test::denoise
