#include <tessera/job/render_job.h>

#include "progress_bar.h"

#include <tessera/axis_order_check.h>
#include <tessera/config/build_scene.h>
#include <tessera/config/device_choice.h>
#include <tessera/config/render_memory.h>
#include <tessera/denoiser.h>
#include <tessera/film.h>
#include <tessera/memory_estimate.h>
#include <tessera/render.h>
#include <tessera/scene_warnings.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>

namespace tessera::job {

VolumeInfo describe_volume(const config::RawVolume& volume, const config::VolumeSpec& spec,
                           const IntegratorDesc& first_integrator) {
  return describe_field(volume.view(), spec.geometry(), first_integrator);
}

VolumeInfo describe_field(const FieldView& view, const VolumeGeometry& geometry,
                          const IntegratorDesc& first_integrator) {
  VolumeInfo v;
  v.view = view;
  v.view.validate("field");
  v.geometry = geometry;
  v.bounds = field_bounds(v.view, v.geometry);
  // One pass: the range (as field_range) and the NaN vertices come with the majorant ranges
  v.summary = FieldSummary::build(v.view, majorant_edge(v.view, first_integrator));
  v.range = {v.summary->value_min(), v.summary->value_max()};
  v.nan_voxels = v.summary->nan_vertices();
  // Same byte count, wrong order: loads fine and renders stripes (a few thousand samples)
  if (const auto s = suspect_axis_order(v.view)) v.warnings.push_back(axis_order_warning(*s, "volume.dims"));
  return v;
}

namespace {

/// `spec` with the command line's overrides of its image and integrator blocks (--width,
/// --height, --spp, --denoise, --tile, --scanline, --seed).
config::RenderSpec with_flags(const config::RenderSpec& spec, const Args& args) {
  config::RenderSpec s = spec;
  if (args.width) s.image.width = *args.width;
  if (args.height) s.image.height = *args.height;
  if (args.spp) s.image.spp = *args.spp;
  if (args.denoise) s.image.denoise = *args.denoise;
  if (args.tile) s.integrator.tile = *args.tile;
  if (args.seed) s.integrator.seed = *args.seed;
  return s;
}

/// The render options of `flagged` (with_flags), with --threads and the step as the frame.
RenderOptions options_for(const config::Config& cfg, const config::RenderSpec& flagged, const Args& args) {
  RenderOptions options = config::build_render_options(flagged, cfg.global);
  if (args.threads) options.threads = *args.threads;
  // The device: the volume is host memory, so auto is the CPU; cuda copies it for the render
  config::GlobalOptions global = cfg.global;
  if (args.device) global.device = *args.device;
  const config::DeviceSelection device = config::resolve_device(global, false, 0);
  options.device = device.device;
  options.cuda_device = device.cuda_device;
  options.device_memory_limit = config::memory_limit(cfg.global).bytes;
  options.frame = static_cast<std::uint64_t>(args.step);  // as the adapter at this step
  return options;
}

/// The render's estimated allocations against the memory limit, before any of them is made
/// (the envmap's header is read, not its pixels); writes the formats of `targets`.
void check_memory(const config::Config& cfg, const config::RenderSpec& spec, const VolumeInfo& volume, const Args& args,
                  const std::vector<OutputTarget>& targets) {
  const config::RenderSpec flagged = with_flags(spec, args);
  std::vector<ImageFormat> formats;
  for (const OutputTarget& t : targets) formats.push_back(t.format);
  const MemoryEstimate estimate = estimate_render_memory(
      config::render_footprint(flagged, options_for(cfg, flagged, args), formats, volume.view, 1));
  const config::MemoryLimit limit = config::memory_limit(cfg.global);
  if (estimate.total() <= limit.bytes) return;
  throw std::runtime_error("render '" + spec.name + "' needs an estimated " + estimate.describe() + ", more than " +
                           limit.text);
}

}  // namespace

SceneDesc scene_for(const config::Config& cfg, const config::RenderSpec& spec, const VolumeInfo& volume,
                    const Args& args) {
  // The flags first: `distance: fit` frames the camera for the image's aspect ratio; a moving
  // orbit is placed at --step, as the adapter places it at that step
  const config::RenderSpec flagged = with_flags(spec, args);
  SceneDesc scene = config::build_scene(flagged, volume.bounds, volume.range, volume.geometry, args.step);
  scene.options = options_for(cfg, flagged, args);
  return scene;
}

void check_volume_memory(const config::Config& cfg) {
  const config::VolumeSpec& v = *cfg.volume;
  // dims are at most 2^31 each and 2^47 vertices in all (parse_volume): no overflow here
  const std::uint64_t bytes = static_cast<std::uint64_t>(v.dims[0]) * static_cast<std::uint64_t>(v.dims[1]) *
                              static_cast<std::uint64_t>(v.dims[2]) * dtype_size(v.dtype);
  const config::MemoryLimit limit = config::memory_limit(cfg.global);
  if (bytes <= limit.bytes) return;
  throw std::runtime_error("volume " + v.file + ": " + std::to_string(v.dims[0]) + "x" + std::to_string(v.dims[1]) +
                           "x" + std::to_string(v.dims[2]) + " values need " + format_bytes(bytes) + ", more than " +
                           limit.text);
}

RenderRecord run_render(const config::Config& cfg, const config::RenderSpec& spec, VolumeInfo& volume, const Args& args,
                        const std::vector<OutputTarget>& targets, bool show_progress) {
  RenderedImage r = render_image(cfg, spec, volume, args, targets, show_progress);
  // Annotations: step and time from --step and --time (as the adapter's call gives them)
  std::optional<AnnotationDesc> annotations;
  if (spec.annotations)
    annotations = config::build_annotations(*spec.annotations, spec.name, spec.field, r.tf, args.step, args.time);
  write_outputs(targets, r.image, spec.output, annotations ? &*annotations : nullptr);
  for (const auto& t : targets) r.record.outputs.push_back(t.path);
  return std::move(r.record);
}

RenderedImage render_image(const config::Config& cfg, const config::RenderSpec& spec, VolumeInfo& volume,
                           const Args& args, const std::vector<OutputTarget>& targets, bool show_progress) {
  using Clock = std::chrono::steady_clock;
  // Limits: the memory estimate before any allocation (the envmap included), then the clock
  check_memory(cfg, spec, volume, args, targets);
  const auto t_begin = Clock::now();
  const double time_limit = args.time_limit.value_or(cfg.global.time_limit);
  SceneDesc scene = scene_for(cfg, spec, volume, args);
  if (time_limit > 0.0)
    scene.options.deadline =
        t_begin + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(time_limit));
  const auto time_limit_passed = [&](const DeadlineExceeded& e) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "render '%s' passed %s = %g s after %.2f s (%zu/%zu tiles done); no image written",
                  spec.name.c_str(), args.time_limit ? "--time-limit" : "tessera.time_limit", time_limit,
                  std::chrono::duration<double>(Clock::now() - t_begin).count(), e.tiles_done(), e.tiles_total());
    return std::runtime_error(buf);
  };

  RenderRecord rec;
  rec.name = spec.name;
  rec.width = scene.image.width;
  rec.height = scene.image.height;
  rec.spp = scene.image.spp;

  // Prepare (majorants, tables, tiles), then render every tile
  const auto t0 = Clock::now();
  PreparedScene prepared;
  try {
    prepared = prepare(volume.view, scene, volume.summary);
  } catch (const DeadlineExceeded& e) {
    throw time_limit_passed(e);
  } catch (const std::invalid_argument& e) {
    // prepare() knows no file: say which file and render the faulty value belongs to
    throw std::invalid_argument(cfg.path + ": render '" + spec.name + "': " + e.what());
  }
  rec.prepare_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  volume.summary = prepared.summary();

  Film film(scene.image.width, scene.image.height, scene.image.denoise);
  ProgressBar bar(spec.name, static_cast<int>(prepared.tiles().size()), show_progress);
  RenderStats stats;
  try {
    render(prepared, film, stats, [&bar](int done) { bar.update(done); });
  } catch (const DeadlineExceeded& e) {
    bar.finish();
    throw time_limit_passed(e);
  } catch (const std::exception& e) {
    // Only the GPU throws here (a CUDA error, or what the device does not cover yet)
    bar.finish();
    throw std::runtime_error("render '" + spec.name + "' on " +
                             config::device_text({scene.options.device, scene.options.cuda_device}) + ": " + e.what() +
                             " (tessera.device: cpu, or --device cpu, renders on the CPU)");
  }
  rec.device = config::device_text({scene.options.device, scene.options.cuda_device});
  bar.finish();
  stats.nan_voxels_seen = volume.nan_voxels;
  rec.stats = stats;
  rec.warnings = volume.warnings;
  for (std::string& w : render_warnings(prepared, stats)) rec.warnings.push_back(std::move(w));

  Image image = film.resolve(spec.output.variance, spec.output.samples);
  if (scene.image.denoise) {
    const auto t_denoise = Clock::now();
    denoise(image, scene.options.threads);  // the PNG shows it, the EXR gains denoised.R/G/B; RGBA stays as rendered
    rec.denoise_seconds = std::chrono::duration<double>(Clock::now() - t_denoise).count();
  }
  return RenderedImage{std::move(rec), std::move(image), scene.tf};
}

}  // namespace tessera::job
