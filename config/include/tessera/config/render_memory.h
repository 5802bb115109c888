#pragma once
/// A render's memory, from its config: what the memory estimate (tessera/memory_estimate.h)
/// needs to know of one render of a spec, and the per-rank limit it is checked against
/// (tessera.memory_limit_mb or its default) with the words messages give that limit. The CLI
/// and the in situ adapter both check a render through these, so each rule is written once
/// (docs/insitu.md and docs/cli.md, "Limits and failure").
#include <tessera/config/config.h>
#include <tessera/field_view.h>
#include <tessera/image_format.h>
#include <tessera/memory_estimate.h>
#include <tessera/scene.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tessera::config {

/// The footprint of one render of `spec` as it will run: its image (size, denoise), the
/// layers of output (variance, samples), `options` (tile; threads, where 0 stands for the
/// machine's hardware threads shared by the `ranks_on_node` ranks of this node, at least one),
/// the `formats` this process writes (none: no writer's buffers), the field rendered (`field`:
/// only its dims are read, for the macrocells of spec.integrator), its `geometry` (which axes
/// are rectilinear: each adds its axis tables; the coordinates are not read) and the envmap's
/// size, read from the file's header. It describes a process that writes the image, keeps no copy of it
/// and renders no Cinema views (writes, keeps_last_image, views): the adapter sets those.
/// Throws like read_exr_size for an envmap it cannot read.
RenderFootprint render_footprint(const RenderSpec& spec, const RenderOptions& options,
                                 std::span<const ImageFormat> formats, const FieldView& field, int ranks_on_node,
                                 const VolumeGeometry& geometry = {});

struct MemoryLimit {
  std::uint64_t bytes = 0;
  /// How the limit was set, for messages: "tessera.memory_limit_mb = 512 MiB", or
  /// "the default tessera.memory_limit_mb (half of the machine's 62.7 GiB: 31.4 GiB)"
  std::string text;
};

/// tessera.memory_limit_mb in bytes, or when it is 0 the default (default_memory_limit_bytes):
/// for a single process (the CLI) without `ranks_on_node`, for one of `ranks_on_node` ranks
/// on this node (the adapter) with it; then the text says so ("... half of the machine's
/// 62.7 GiB over 4 rank(s) on this node: 7.84 GiB)").
MemoryLimit memory_limit(const GlobalOptions& global, std::optional<int> ranks_on_node = std::nullopt);

}  // namespace tessera::config
