#include "render_job.h"

#include "progress_bar.h"

#include <tessera/config/build_scene.h>
#include <tessera/film.h>
#include <tessera/render.h>

#include <chrono>

namespace tessera::cli {

VolumeInfo describe_volume(const config::RawVolume& volume, const config::VolumeSpec& spec,
                           const IntegratorDesc& first_integrator) {
  VolumeInfo v;
  v.view = volume.view();
  v.view.validate("field");
  v.geometry = spec.geometry();
  v.bounds = field_bounds(v.view, v.geometry);
  // One pass: the range (as field_range) and the NaN vertices come with the majorant ranges
  v.summary = FieldSummary::build(v.view, majorant_edge(v.view, first_integrator));
  v.range = {v.summary->value_min(), v.summary->value_max()};
  v.nan_voxels = v.summary->nan_vertices();
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
                        VolumeInfo& volume, const Args& args,
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
  const PreparedScene prepared = prepare(volume.view, scene, volume.summary);
  rec.prepare_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  volume.summary = prepared.summary();

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
