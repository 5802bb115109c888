// A render's memory from its config (render_memory.h): the footprint the CLI and the adapter
// both estimate, and the limit with the words their messages give it.
#include "test_support.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/render_memory.h>
#include <tessera/field_summary.h>
#include <tessera/film.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <thread>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;

TEST_CASE("render_footprint: image, layers, formats, tile, threads and macrocells from the spec",
          "[config][render_memory]") {
  const Config c = parse_config(R"(renders:
  - name: a
    image: {width: 64, height: 48, spp: 3, denoise: true}
    camera: {position: [3, 0, 0]}
    transfer_function: {opacity: [[0, 1]]}
    integrator: {tile: 16}
    output: {formats: [png], variance: true}
)",
                                "scene.yaml", "");
  const RenderSpec& spec = c.renders[0];
  FieldView field;
  field.dims[0] = 33;
  field.dims[1] = 17;
  field.dims[2] = 9;
  RenderOptions options = build_render_options(spec, c.global);
  options.threads = 3;
  const ImageFormat png[] = {ImageFormat::Png};
  const RenderFootprint f = render_footprint(spec, options, png, field, 4);
  CHECK(f.width == 64);
  CHECK(f.height == 48);
  CHECK(f.denoise);
  CHECK(f.variance);
  CHECK_FALSE(f.samples);
  CHECK(f.formats == std::vector<ImageFormat>{ImageFormat::Png});
  CHECK(f.tile == 16);
  CHECK(f.threads == 3);
  CHECK(f.field_dims[0] == 33);
  CHECK(f.field_dims[2] == 9);
  CHECK(f.macrocell_edge == majorant_edge(field, spec.integrator.desc));
  CHECK(f.envmap_width == 0);
  // What the caller says: this process writes, keeps nothing, renders no Cinema views
  CHECK(f.writes);
  CHECK_FALSE(f.keeps_last_image);
  CHECK(f.views == 0);
  // threads 0: the hardware threads shared by the node's ranks, at least one
  options.threads = 0;
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  CHECK(render_footprint(spec, options, png, field, 1).threads == std::max(1, hardware));
  CHECK(render_footprint(spec, options, png, field, 1 << 20).threads == 1);
  // Rectilinear axes: from the geometry (its coordinates are not read); uniform by default
  for (int a = 0; a < 3; ++a) CHECK_FALSE(f.rectilinear[a]);
  VolumeGeometry g;
  const double never_read = 0.0;
  g.coords[2] = &never_read;
  const RenderFootprint r = render_footprint(spec, options, png, field, 4, g);
  CHECK_FALSE(r.rectilinear[0]);
  CHECK_FALSE(r.rectilinear[1]);
  CHECK(r.rectilinear[2]);
  CHECK_THAT(estimate_render_memory(r).describe(), Contains("axis tables"));
  CHECK_THAT(estimate_render_memory(f).describe(), !Contains("axis tables"));
  // On the CUDA device: a call's host copies of its pixels, beside the film (with the
  // auxiliary sums here: image.denoise)
  CHECK_FALSE(f.gpu);
  options.threads = 3;
  options.device = Device::Cuda;
  const RenderFootprint gpu = render_footprint(spec, options, png, field, 4);
  CHECK(gpu.gpu);
  const std::uint64_t pixels = 64 * 48;
  CHECK(estimate_render_memory(gpu).total() - estimate_render_memory(f).total() ==
        pixels * (kGpuHostBytesPerPixel + sizeof(AuxSums)));
  CHECK_THAT(estimate_render_memory(gpu).describe(), Contains("GPU call's host copies"));
  // ... adaptive sampling's two passes: twice the copies and 12 bytes more per pixel
  CHECK_FALSE(gpu.adaptive);
  RenderSpec adaptive_spec = spec;
  adaptive_spec.image.target_error = 0.05;
  const RenderFootprint adaptive = render_footprint(adaptive_spec, options, png, field, 4);
  CHECK(adaptive.adaptive);
  CHECK(estimate_render_memory(adaptive).total() - estimate_render_memory(gpu).total() ==
        pixels * (kGpuHostBytesPerPixel + sizeof(AuxSums) + 12));
}

TEST_CASE("memory_limit: tessera.memory_limit_mb, or the default for a process or a node's ranks",
          "[config][render_memory]") {
  GlobalOptions global;
  global.memory_limit_mb = 512;
  const MemoryLimit set = memory_limit(global, 4);
  CHECK(set.bytes == std::uint64_t{512} << 20);
  CHECK(set.text == "tessera.memory_limit_mb = 512 MiB");
  global.memory_limit_mb = 0;
  const std::string machine = format_bytes(physical_memory_bytes());
  const MemoryLimit cli = memory_limit(global);
  CHECK(cli.bytes == default_memory_limit_bytes(1));
  CHECK(cli.text ==
        "the default tessera.memory_limit_mb (half of the machine's " + machine + ": " + format_bytes(cli.bytes) + ")");
  const MemoryLimit rank = memory_limit(global, 4);
  CHECK(rank.bytes == default_memory_limit_bytes(4));
  CHECK(rank.text == "the default tessera.memory_limit_mb (half of the machine's " + machine +
                         " over 4 rank(s) on this node: " + format_bytes(rank.bytes) + ")");
}
