#include <tessera/config/render_memory.h>

#include <tessera/field_summary.h>
#include <tessera/image_io.h>

#include <algorithm>
#include <thread>

namespace tessera::config {

RenderFootprint render_footprint(const RenderSpec& spec, const RenderOptions& options,
                                 std::span<const ImageFormat> formats, const FieldView& field, int ranks_on_node,
                                 const VolumeGeometry& geometry) {
  RenderFootprint f;
  f.width = spec.image.width;
  f.height = spec.image.height;
  f.tile = options.tile;
  f.threads = options.threads > 0
                  ? options.threads
                  : std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / std::max(1, ranks_on_node));
  f.variance = spec.output.variance;
  f.samples = spec.output.samples;
  f.denoise = spec.image.denoise;
  f.gpu = options.device == Device::Cuda;
  f.adaptive = spec.image.target_error > 0.0;
  f.formats.assign(formats.begin(), formats.end());
  for (int a = 0; a < 3; ++a) {
    f.field_dims[a] = field.dims[a];
    f.rectilinear[a] = geometry.coords[a] != nullptr;
  }
  f.macrocell_edge = majorant_edge(field, spec.integrator.desc);
  if (spec.background.type == BackgroundType::EnvMap) {
    const auto [w, h] = read_exr_size(spec.background.file);  // the header only
    f.envmap_width = w;
    f.envmap_height = h;
  }
  return f;
}

MemoryLimit memory_limit(const GlobalOptions& global, std::optional<int> ranks_on_node) {
  const std::int64_t mb = global.memory_limit_mb;
  if (mb > 0) return {static_cast<std::uint64_t>(mb) << 20, "tessera.memory_limit_mb = " + std::to_string(mb) + " MiB"};
  const int ranks = std::max(1, ranks_on_node.value_or(1));
  const std::uint64_t bytes = default_memory_limit_bytes(ranks);
  const std::string over = ranks_on_node ? " over " + std::to_string(ranks) + " rank(s) on this node" : "";
  return {bytes, "the default tessera.memory_limit_mb (half of the machine's " + format_bytes(physical_memory_bytes()) +
                     over + ": " + format_bytes(bytes) + ")"};
}

}  // namespace tessera::config
