#include "render_job.h"

#include "progress_bar.h"

#include <tessera/config/build_scene.h>
#include <tessera/film.h>
#include <tessera/render.h>

#include <chrono>
#include <cmath>

namespace tessera::cli {

VolumeInfo describe_volume(const config::RawVolume& volume, const config::VolumeSpec& spec) {
  VolumeInfo v;
  v.view = volume.view();
  v.geometry = spec.geometry();
  v.bounds = field_bounds(v.view, v.geometry);
  v.range = field_range(v.view);

  // NaN vertices, reported in the statistics
  v.nan_voxels = dispatch_dtype(v.view, [&](auto f) {
    std::uint64_t n = 0;
    for (std::int64_t k = 0; k < v.view.dims[2]; ++k)
      for (std::int64_t j = 0; j < v.view.dims[1]; ++j)
        for (std::int64_t i = 0; i < v.view.dims[0]; ++i) n += std::isnan(f.load(i, j, k)) ? 1 : 0;
    return n;
  });
  return v;
}

SceneDesc scene_for(const config::Config& cfg, const config::RenderSpec& spec,
                    const VolumeInfo& volume, const Args& args) {
  SceneDesc scene = config::build_scene(spec, volume.bounds, volume.range, volume.geometry);
  scene.options = config::build_render_options(spec, cfg.global);
  if (args.spp) scene.image.spp = *args.spp;
  if (args.width) scene.image.width = *args.width;
  if (args.height) scene.image.height = *args.height;
  if (args.tile) scene.options.tile = *args.tile;
  if (args.threads) scene.options.threads = *args.threads;
  if (args.seed) scene.options.seed = *args.seed;
  return scene;
}

RenderRecord run_render(const config::Config& cfg, const config::RenderSpec& spec,
                        const VolumeInfo& volume, const Args& args,
                        const std::vector<OutputTarget>& targets, bool show_progress) {
  using Clock = std::chrono::steady_clock;
  const SceneDesc scene = scene_for(cfg, spec, volume, args);

  RenderRecord rec;
  rec.name = spec.name;
  rec.width = scene.image.width;
  rec.height = scene.image.height;
  rec.spp = scene.image.spp;

  // Prepare (majorants, tables, tiles), then render every tile
  const auto t0 = Clock::now();
  const PreparedScene prepared = prepare(volume.view, scene);
  rec.prepare_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  Film film(scene.image.width, scene.image.height);
  ProgressBar bar(spec.name, static_cast<int>(prepared.tiles().size()), show_progress);
  RenderStats stats;
  render(prepared, film, stats, [&bar](int done) { bar.update(done); });
  bar.finish();
  stats.nan_voxels_seen = volume.nan_voxels;
  rec.stats = stats;

  // Write
  const Image image = film.resolve(spec.output.variance, spec.output.samples);
  write_outputs(targets, image, spec.output);
  for (const auto& t : targets) rec.outputs.push_back(t.path);
  return rec;
}

}  // namespace tessera::cli
