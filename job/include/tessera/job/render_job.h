#pragma once
// One render of the CLI: scene from the spec, flag overrides, prepare, render, write.
#include <tessera/config/config.h>
#include <tessera/config/raw_volume.h>
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/image.h>
#include <tessera/job/args.h>
#include <tessera/job/output_files.h>
#include <tessera/job/stats_json.h>
#include <tessera/scene.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace tessera::job {

/// What every render needs to know about the volume, computed once.
struct VolumeInfo {
  FieldView view;
  VolumeGeometry geometry;
  Bounds bounds;
  std::pair<double, double> range;  ///< finite min and max, for `range: auto`
  std::uint64_t nan_voxels = 0;
  /// The one pass over the values (range and NaN count come from it), for `edge`; renders
  /// with that macrocell edge prepare from it, run_render replaces it for another edge.
  std::shared_ptr<const FieldSummary> summary;
  /// What the data itself suggests is wrong (dims in a suspicious order), for every render.
  std::vector<std::string> warnings;
};

/// Reads the volume once: a FieldSummary for macrocell edge `edge` (majorant_edge of the
/// first render), its finite range and NaN count.
VolumeInfo describe_volume(const config::RawVolume& volume, const config::VolumeSpec& spec,
                           const IntegratorDesc& first_integrator);

/// As describe_volume, for a field that is already in memory (the Python package's numpy
/// array, read in place): validates `view` (std::invalid_argument naming "field").
VolumeInfo describe_field(const FieldView& view, const VolumeGeometry& geometry,
                          const IntegratorDesc& first_integrator);

/// The scene for `spec` with the command line's overrides (--spp, --width, --height, --tile,
/// --scanline, --threads, --seed) applied over the YAML.
SceneDesc scene_for(const config::Config& cfg, const config::RenderSpec& spec, const VolumeInfo& volume,
                    const Args& args);

/// Renders and writes one image; the returned record holds its statistics and outputs.
/// volume.summary is reused when it has the render's macrocell edge, else replaced.
/// The volume's values against tessera.memory_limit_mb (or its default), before the file is
/// read: a sparse or huge file must fail with the size and the limit, not exhaust memory.
void check_volume_memory(const config::Config& cfg);

RenderRecord run_render(const config::Config& cfg, const config::RenderSpec& spec, VolumeInfo& volume, const Args& args,
                        const std::vector<OutputTarget>& targets, bool show_progress);

/// One render's image and its record (outputs empty): run_render without the writing.
struct RenderedImage {
  RenderRecord record;
  Image image;          ///< film.resolve(output.variance, output.samples): what the EXR holds
  TransferFunction tf;  ///< the render's TF, range resolved: what a colour bar shows
};

/// Everything run_render does before writing: the memory check (against `targets`' formats;
/// none = no image buffers), scene, time limit, prepare, render, warnings. tessera.render
/// (python/) calls it with default Args and no targets, so its pixels are the CLI's.
RenderedImage render_image(const config::Config& cfg, const config::RenderSpec& spec, VolumeInfo& volume,
                           const Args& args, const std::vector<OutputTarget>& targets, bool show_progress);

}  // namespace tessera::job
