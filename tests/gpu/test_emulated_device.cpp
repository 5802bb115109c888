// The GPU backend's host half on the host emulation of a GPU (cuda/emulated_device.h), in
// every build: what only the device path does, checked without a GPU. The device copies hold
// everything the kernel reads (the caller's arrays are overwritten after the first call and
// the image does not change), device memory is read in place (and overwriting it does change
// the image), the call's buffers are released, limits refuse by name before allocating, a
// split of the tiles or a second call gives the CPU's sums, the deadline stops between
// slices. (test_gpu_render.cpp and test_gpu_values.cpp run here too: every Value against the
// CPU, counters equal, sums equal to rounding.)
#include "gpu_test_util.h"
#include "two_levels.h"
#include "warped_mesh.h"

#include "cuda/device_render.h"
#include "cuda/device_scene.h"
#include "cuda/emulated_device.h"
#include "cuda/pixel_kernel.h"
#include "kernels/wave_scratch.h"
#include "mesh/mesh_layout.h"
#include "scene/prepared_scene_impl.h"

#include <tessera/amr.h>
#include <tessera/magnitude_field.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

using namespace gpu_test;
using tessera::cuda::DeviceBackend;
using tessera::cuda::EmulatedDevice;

namespace {

constexpr int kN = 24;

tessera::Film render_on(const std::shared_ptr<DeviceBackend>& b, const tessera::PreparedScene& ps,
                        tessera::CudaTransfer* tr = nullptr, tessera::RenderStats* stats = nullptr,
                        const tessera::CudaLaunch& launch = {}, bool aux = false) {
  tessera::Film film(ps.desc().image.width, ps.desc().image.height, aux);
  tessera::RenderStats st;
  tessera::cuda::render_on_device(b, ps, all_tiles(ps), film, st, launch, tr);
  if (stats) *stats = st;
  return film;
}

}  // namespace

TEST_CASE("Sample lanes: min(32, spp, 2^22 / pixels), at least 1", "[emulated]") {
  using tessera::cuda::sample_lanes;
  CHECK(sample_lanes(128, 128, 256) == 32);  // one warp per pixel
  CHECK(sample_lanes(128, 128, 64) == 32);
  CHECK(sample_lanes(128, 128, 5) == 5);      // never more lanes than samples
  CHECK(sample_lanes(1024, 1024, 256) == 4);  // 2^22 lane sums at most
  CHECK(sample_lanes(4096, 4096, 256) == 1);
  CHECK(sample_lanes(1, 1, 1) == 1);
}

TEST_CASE("Emulated device: the device copies hold every array the kernel reads", "[emulated]") {
  // A float32 field (widened on the device) on rectilinear axes: after the first call the
  // caller's values and coordinates are overwritten; a second call reuses the device copies
  // and renders the same bits
  std::vector<float> field = heat_field<float>(kN);
  std::vector<double> x = stretched(kN, 1.3), y = stretched(kN, 0.9), z = stretched(kN, 1.0);
  tessera::SceneDesc s = heat_scene(kN, 5);
  s.geometry.coords[0] = x.data();
  s.geometry.coords[1] = y.data();
  s.geometry.coords[2] = z.data();
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN), s);
  const auto b = tessera::cuda::emulated_backend();
  tessera::CudaTransfer first, second;
  const tessera::Film a = render_on(b, ps, &first);
  std::fill(field.begin(), field.end(), -7.0e30f);
  std::fill(x.begin(), x.end(), 1.0e300);
  std::fill(y.begin(), y.end(), -1.0e300);
  std::fill(z.begin(), z.end(), 0.0);
  const tessera::Film again = render_on(b, ps, &second);
  CHECK_FALSE(first.scene_reused);
  CHECK(second.scene_reused);
  CHECK_FALSE(first.field_in_place);
  CHECK(second.bytes_to_device < first.bytes_to_device);
  CHECK(first.bytes_to_device >= field.size() * sizeof(float));
  CHECK(same_bits(a, again));
}

TEST_CASE("Emulated device: refinement levels' tables and patches are all copied", "[emulated]") {
  constexpr std::int64_t n0 = 12;
  std::vector<double> l0(static_cast<std::size_t>(n0 * n0 * n0)), l1(static_cast<std::size_t>(12 * 14 * 12));
  for (std::size_t i = 0; i < l0.size(); ++i) l0[i] = 300.0 + 900.0 * std::sin(0.37 * static_cast<double>(i));
  for (std::size_t i = 0; i < l1.size(); ++i) l1[i] = 300.0 + 900.0 * std::cos(0.11 * static_cast<double>(i));
  const std::int64_t off0[3] = {0, 0, 0}, dims0[3] = {n0, n0, n0}, off1[3] = {6, 4, 6}, dims1[3] = {12, 14, 12};
  const std::vector<tessera::AmrPatch> patches = {
      tessera_test::contiguous_patch(0, off0, l0.data(), tessera::DType::Float64, dims0),
      tessera_test::contiguous_patch(1, off1, l1.data(), tessera::DType::Float64, dims1)};
  const tessera::AmrField amr = tessera_test::two_levels(tessera::DType::Float64, n0, patches);
  tessera::SceneDesc s = heat_scene(kN, 3);
  s.geometry.association = tessera::Association::Cell;
  s.geometry.spacing = Vec3(1.0 / n0);
  const tessera::PreparedScene ps = tessera::prepare(amr, s, nullptr);
  const auto b = tessera::cuda::emulated_backend();
  tessera::RenderStats est, cst;
  const tessera::Film a = render_on(b, ps, nullptr, &est);
  tessera::Film cpu(ps.desc().image.width, ps.desc().image.height);
  tessera::render(ps, cpu, cst);
  CHECK(est.real_collisions == cst.real_collisions);
  CHECK(est.null_collisions == cst.null_collisions);
  CHECK(max_pixel_difference(a, cpu) < 1e-12);
  std::fill(l0.begin(), l0.end(), 1.0e30);
  std::fill(l1.begin(), l1.end(), -1.0e30);
  CHECK(same_bits(a, render_on(b, ps)));
}

TEST_CASE("Emulated device: device memory is read in place, not copied", "[emulated]") {
  std::vector<double> field = heat_field<double>(kN);
  const std::size_t bytes = field.size() * sizeof(double);
  EmulatedDevice d;
  d.device_ranges.emplace_back(field.data(), bytes);
  const auto on_device = tessera::cuda::emulated_backend(d);
  const auto copying = tessera::cuda::emulated_backend();
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), heat_scene(kN, 8));
  tessera::CudaTransfer copied, in_place;
  const tessera::Film a = render_on(copying, ps, &copied);
  // A prepared scene keeps the copies of one backend: a fresh scene for the other
  const tessera::PreparedScene ps2 =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), heat_scene(kN, 8));
  const tessera::Film b = render_on(on_device, ps2, &in_place);
  CHECK(in_place.field_in_place);
  CHECK_FALSE(copied.field_in_place);
  CHECK(copied.bytes_to_device - in_place.bytes_to_device == bytes);
  CHECK(same_bits(a, b));
  // Read in place: new values on the device change the next image (prepared scenes assume
  // unchanged values; a render after a change shows that nothing was copied)
  for (double& v : field) v = 300.0;
  const tessera::Film c = render_on(on_device, ps2);
  CHECK_FALSE(same_bits(b, c));
}

TEST_CASE("Emulated device: a call releases its buffers, the scene's copies go with the scene", "[emulated]") {
  const std::vector<double> field = heat_field<double>(kN);
  const auto b = tessera::cuda::emulated_backend();
  tessera::CudaTransfer tr;
  {
    const tessera::PreparedScene ps =
        tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), heat_scene(kN, 2));
    (void)render_on(b, ps, &tr);
    const std::size_t held = tessera::cuda::emulated_bytes_held(*b);
    INFO("held after the call " << held << ", peak " << tr.device_bytes);
    CHECK(held > field.size() * sizeof(double));  // the field's copy (and the tables) stay
    CHECK(held < tr.device_bytes);                // the pixel sums and lanes went
  }
  CHECK(tessera::cuda::emulated_bytes_held(*b) == 0);
}

TEST_CASE("Emulated device: memory limits refuse by name before allocating", "[emulated]") {
  const std::vector<double> field = heat_field<double>(kN);
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), heat_scene(kN, 2));
  EmulatedDevice small;
  small.name = "tiny emulated GPU";
  small.memory_bytes = 64 * 1024;
  const auto b = tessera::cuda::emulated_backend(small);
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  CHECK_THROWS_WITH(tessera::cuda::render_on_device(b, ps, all_tiles(ps), film, st, {}, nullptr),
                    Catch::Contains("tiny emulated GPU has 65536 bytes") && Catch::Contains("free of"));
  CHECK(tessera::cuda::emulated_bytes_held(*b) == 0);
  tessera::CudaLaunch limited;
  limited.memory_limit_bytes = 100000;
  const auto big = tessera::cuda::emulated_backend();
  CHECK_THROWS_WITH(tessera::cuda::render_on_device(big, ps, all_tiles(ps), film, st, limited, nullptr),
                    Catch::Contains("over the memory limit of 100000 bytes"));
  CHECK(tessera::cuda::emulated_bytes_held(*big) == 0);
  CHECK(st.samples == 0);
}

TEST_CASE("Emulated device: the wavefront's path slots count in the memory limit and go with the call", "[emulated]") {
  const std::vector<double> field = heat_field<double>(kN);
  const auto backend = [](tessera::cuda::LaneLoop loop) {
    EmulatedDevice d;
    d.lane_loop = loop;
    d.wave.slots = 64;
    return tessera::cuda::emulated_backend(d);
  };
  const auto regen = backend(tessera::cuda::LaneLoop::Regenerate);
  const auto wave = backend(tessera::cuda::LaneLoop::Wavefront);
  const std::size_t slots = tessera::cuda::wave_scratch_bytes(1 << 20, 64);  // 64 slots: fewer than the lanes
  CHECK(slots == 256 + 4 * 256 + 64 * tessera::cuda::kWaveSlotBytes);
  const auto prepared = [&] {
    return tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN),
                            heat_scene(kN, 2));
  };
  const tessera::PreparedScene pr = prepared(), pw = prepared();
  tessera::CudaTransfer tr, tw;
  const tessera::Film a = render_on(regen, pr, &tr);
  const tessera::Film b = render_on(wave, pw, &tw);
  CHECK(same_bits(a, b));
  CHECK(tw.device_bytes == tr.device_bytes + slots);
  CHECK(tessera::cuda::emulated_bytes_held(*wave) == tessera::cuda::emulated_bytes_held(*regen));
  // A limit the other loop keeps refuses the wavefront by name, before anything is drawn
  tessera::CudaLaunch limited;
  limited.memory_limit_bytes = tr.device_bytes + slots / 2;
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  const tessera::PreparedScene pr2 = prepared(), pw2 = prepared();
  CHECK_NOTHROW(tessera::cuda::render_on_device(regen, pr2, all_tiles(pr2), film, st, limited, nullptr));
  tessera::RenderStats sw;
  CHECK_THROWS_WITH(tessera::cuda::render_on_device(wave, pw2, all_tiles(pw2), film, sw, limited, nullptr),
                    Catch::Contains("over the memory limit of " + std::to_string(limited.memory_limit_bytes)));
  CHECK(sw.samples == 0);
}

TEST_CASE("Emulated device: any split of the tiles and a second call give the CPU's sums", "[emulated]") {
  const std::vector<std::uint16_t> field = [] {
    const std::vector<double> h = heat_field<double>(kN);
    std::vector<std::uint16_t> v(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) v[i] = static_cast<std::uint16_t>(h[i] * 20.0);
    return v;
  }();
  tessera::SceneDesc s = heat_scene(kN, 4);
  s.tf.lo = 6000.0;
  s.tf.hi = 26000.0;
  s.options.tile = 16;
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::UInt16, kN, kN, kN), s);
  const auto b = tessera::cuda::emulated_backend();
  const tessera::Film whole = render_on(b, ps);
  // The tiles in reverse order, one call each, with odd slices
  std::vector<int> tiles = all_tiles(ps);
  REQUIRE(tiles.size() > 2);
  std::reverse(tiles.begin(), tiles.end());
  tessera::Film split(48, 48);
  tessera::RenderStats st;
  tessera::CudaLaunch odd;
  odd.samples_per_launch = 7;
  odd.pixels_per_launch = 100;
  for (const int t : tiles)
    tessera::cuda::render_on_device(b, ps, std::span<const int>(&t, 1), split, st, odd, nullptr);
  CHECK(same_bits(whole, split));
  // A second call continues each pixel's sample indices, as the CPU's render_tiles does
  tessera::Film twice_gpu(48, 48, true), twice_cpu(48, 48, true);
  tessera::RenderStats gst, cst;
  for (int i = 0; i < 2; ++i) {
    tessera::cuda::render_on_device(b, ps, all_tiles(ps), twice_gpu, gst, {}, nullptr);
    tessera::render_tiles(ps, all_tiles(ps), twice_cpu, cst);
  }
  CHECK(gst.samples == cst.samples);
  CHECK(gst.real_collisions == cst.real_collisions);
  CHECK(max_pixel_difference(twice_gpu, twice_cpu) < 1e-12);
  // ... and the denoiser's features
  double aux_diff = 0.0;
  for (std::size_t i = 0; i < twice_cpu.aux().size(); ++i)
    for (int c = 0; c < 3; ++c) {
      aux_diff = std::fmax(aux_diff, std::fabs(twice_cpu.aux()[i].albedo[c] - twice_gpu.aux()[i].albedo[c]));
      aux_diff = std::fmax(aux_diff, std::fabs(twice_cpu.aux()[i].normal[c] - twice_gpu.aux()[i].normal[c]));
    }
  CHECK(aux_diff < 1e-9);
}

TEST_CASE("Emulated device: adaptive sampling gives the CPU's counts and sums for any split of the tiles",
          "[emulated]") {
  // Tiles of 12 pixels straddle the 8x8 blocks, so a tile's blocks reach into its neighbours:
  // one call per tile redraws the pilots the CPU's tile redraws (the same lookups); one call of
  // all tiles draws each pilot once (the same samples and sums)
  const std::vector<double> field = heat_field<double>(kN);
  tessera::SceneDesc s = heat_scene(kN, 31);
  s.image = {44, 36, 48, 0.06};
  s.options.tile = 12;
  s.camera.fov_deg = 60.0;  // some tiles culled
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), s);
  const auto b = tessera::cuda::emulated_backend();
  std::vector<int> tiles = all_tiles(ps);
  std::reverse(tiles.begin(), tiles.end());
  tessera::Film cpu(44, 36, true), split(44, 36, true);
  tessera::RenderStats cst, gst;
  tessera::CudaLaunch odd;
  odd.samples_per_launch = 5;
  odd.pixels_per_launch = 37;
  for (const int t : tiles) {
    tessera::render_tiles(ps, std::span<const int>(&t, 1), cpu, cst);
    tessera::cuda::render_on_device(b, ps, std::span<const int>(&t, 1), split, gst, odd, nullptr);
  }
  INFO("samples " << gst.samples << " of " << 44 * 36 * 48 << ", tiles culled " << gst.tiles_skipped);
  CHECK(gst.tiles_skipped > 0);
  CHECK(gst.tiles_skipped < gst.tiles_total);
  CHECK(gst.samples < std::uint64_t{44 * 36 * 48} * 3 / 4);
  tessera_test::check_same_paths(gst, cst);
  CHECK(max_pixel_difference(split, cpu) < 1e-12);
  double aux_diff = 0.0;
  for (std::size_t i = 0; i < cpu.aux().size(); ++i)
    for (int c = 0; c < 3; ++c)
      aux_diff = std::fmax(aux_diff, std::fabs(cpu.aux()[i].albedo[c] - split.aux()[i].albedo[c]));
  CHECK(aux_diff < 1e-9);
  // One call of every tile: the same samples drawn and the same image
  tessera::Film whole(44, 36, true);
  tessera::RenderStats wst;
  tessera::cuda::render_on_device(b, ps, all_tiles(ps), whole, wst, {}, nullptr);
  CHECK(wst.samples == cst.samples);
  CHECK(wst.real_collisions <= cst.real_collisions);
  CHECK(max_pixel_difference(whole, cpu) < 1e-12);
}

namespace {

/// heat_scene with what the last bounce and the shadow estimators can meet: two rect lights
/// and two sphere lights (one inside the volume) before the gradient background, few
/// bounces, BRDF shading with a specular lobe and delta-tracking shadows without roulette
/// (variant 1), or the fixed-step march with phase shading under an envmap sky (variant 2).
tessera::SceneDesc loop_scene(int variant) {
  tessera::SceneDesc s = heat_scene(kN, 11);
  if (variant == 0) return s;
  tessera::RectLightDesc r;
  r.position = Vec3(-1.5, 0.5, 0.5);
  r.target = Vec3(0.5, 0.5, 0.5);
  r.width = r.height = 0.6;
  r.radiance = Color(3.0, 2.0, 1.0);
  s.lights.push_back(r);
  tessera::SphereLightDesc a, b;
  a.center = Vec3(0.5, 0.45, 0.55);
  a.radius = 0.12;
  a.radiance = Color(2.0);
  b.center = Vec3(2.0, 1.8, 0.5);
  b.radius = 0.3;
  b.radiance = Color(1.0, 2.0, 4.0);
  s.lights.push_back(a);
  s.lights.push_back(b);
  if (variant == 1) {
    s.integrator.max_bounces = 2;
    s.integrator.shading = tessera::Shading::Brdf;
    s.tf.specular = tessera::ColorTF({0.0, 1.0}, {Color(0.04), Color(0.5)});
    s.tf.roughness = tessera::ScalarTF({0.0, 1.0}, {0.2, 0.6});
    s.integrator.shadow = tessera::ShadowMode::Delta;
    s.integrator.shadow_roulette = false;
  } else {
    s.background = {};
    s.background.type = tessera::BackgroundType::EnvMap;
    s.background.envmap = test_envmap(16, 8);
    s.integrator.max_bounces = 3;
    s.integrator.free_path = tessera::FreePath::Raymarch;
    s.integrator.shading = tessera::Shading::Phase;
    s.integrator.phase_g = 0.4;
  }
  return s;
}

}  // namespace

TEST_CASE("Emulated device: path regeneration, the step-level loops and the wavefront give the per-sample loop's sums "
          "bit for bit",
          "[emulated]") {
  // The lane loops (kernels/lane_loop.h) on scenes that exercise every way a path ends:
  // multiple scattering with Russian roulette and the last bounce, single scattering, both
  // samplers, culled tiles, a pixel's samples split over slices, and the denoiser's features;
  // several lights of both kinds, both shadow estimators and both free-path strategies
  const auto loop_backend = [](tessera::cuda::LaneLoop loop) {
    EmulatedDevice d;
    d.lane_loop = loop;
    return tessera::cuda::emulated_backend(d);
  };
  const auto per_sample = loop_backend(tessera::cuda::LaneLoop::PerSample);
  const auto regenerate = loop_backend(tessera::cuda::LaneLoop::Regenerate);
  const auto steps = loop_backend(tessera::cuda::LaneLoop::Step);
  const auto deferred = loop_backend(tessera::cuda::LaneLoop::StepDefer);
  const auto wavefront = loop_backend(tessera::cuda::LaneLoop::Wavefront);
  EmulatedDevice few;  // the wavefront with 7 path slots (each takes many lanes) and 1 step a round
  few.lane_loop = tessera::cuda::LaneLoop::Wavefront;
  few.wave = {7, 1};
  const auto wave_few = tessera::cuda::emulated_backend(few);
  const std::vector<std::int16_t> field = heat_field<std::int16_t>(kN);
  for (int variant = 0; variant < 3; ++variant)
    for (const auto scattering : {tessera::Scattering::Multiple, tessera::Scattering::Single})
      for (const auto sampler : {tessera::SamplerKind::Sobol, tessera::SamplerKind::Independent}) {
        tessera::SceneDesc s = loop_scene(variant);
        s.integrator.scattering = scattering;
        s.integrator.sampler = sampler;
        s.integrator.rr_depth = 2;
        s.camera.fov_deg = 80.0;  // tiles that see neither the volume nor the light: culled
        s.options.tile = 8;
        const tessera::PreparedScene ps =
            tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Int16, kN, kN, kN), s);
        tessera::CudaLaunch odd;  // a pixel's samples over several slices, lanes cut mid-sample list
        odd.samples_per_launch = 5;
        odd.pixels_per_launch = 300;
        tessera::RenderStats a_st;
        const tessera::Film a = render_on(per_sample, ps, nullptr, &a_st, odd, true);
        CHECK(a_st.tiles_skipped > 0);
        CHECK(a_st.transmittance_lookups > 0);
        for (const auto& other : {regenerate, steps, deferred, wavefront, wave_few}) {
          tessera::RenderStats b_st;
          const tessera::Film b = render_on(other, ps, nullptr, &b_st, odd, true);
          INFO("variant " << variant << ", scattering " << static_cast<int>(scattering) << ", sampler "
                          << static_cast<int>(sampler) << ", loop "
                          << (other == steps       ? "step"
                              : other == deferred  ? "step-defer"
                              : other == wavefront ? "wavefront"
                              : other == wave_few  ? "wavefront, 7 slots, 1 step a round"
                                                   : "regenerate"));
          check_same_paths(a_st, b_st);
          CHECK(same_bits(a, b));
          REQUIRE(a.aux().size() == b.aux().size());
          CHECK(std::memcmp(a.aux().data(), b.aux().data(), a.aux().size() * sizeof(tessera::AuxSums)) == 0);
        }
      }
}

TEST_CASE("Emulated device: the deadline stops the render between slices", "[emulated]") {
  const std::vector<double> field = heat_field<double>(kN);
  tessera::SceneDesc s = heat_scene(kN, 6);
  s.options.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), s);
  const auto b = tessera::cuda::emulated_backend();
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  tessera::CudaTransfer tr;
  CHECK_THROWS_AS(tessera::cuda::render_on_device(b, ps, all_tiles(ps), film, st, {}, &tr), tessera::DeadlineExceeded);
  CHECK(tr.launches == 0);
  CHECK(st.samples == 0);
}

namespace {

/// The heat scene at `seed`, adaptive (64 spp, a pilot of 8, target error 0.05), over `field`
/// (kN^3 float64), for `device`, with `deadline`.
tessera::PreparedScene adaptive_heat(const std::vector<double>& field, std::uint64_t seed, tessera::Device device,
                                     std::chrono::steady_clock::time_point deadline) {
  tessera::SceneDesc s = heat_scene(kN, seed);
  s.image.spp = 64;
  s.image.target_error = 0.05;
  s.options.device = device;
  s.options.deadline = deadline;
  return tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), s);
}

}  // namespace

TEST_CASE("Emulated device: a deadline in the adaptive pilot keeps the pilot samples drawn", "[emulated]") {
  // One pilot sample per slice; after the second slice the test waits the deadline out, so
  // the render stops inside the pilot: every pixel keeps its two samples, the counts are
  // never decided, and the call says the deadline passed
  const std::vector<double> field = heat_field<double>(kN);
  const auto deadline = test_deadline();
  const tessera::PreparedScene ps = adaptive_heat(field, 7, tessera::Device::Cpu, deadline);
  const auto [film, st, tr] = render_cut_by_deadline(ps, deadline, 2);
  CHECK(tr.launches == 2);
  CHECK(st.samples == std::uint64_t{48 * 48 * 2});
  bool two_each = true;
  for (const tessera::PixelSums& p : film.pixels()) two_each &= p.n == 2 && p.drawn == 2;
  CHECK(two_each);
}

TEST_CASE("Emulated device: a GPU render's preview, made on the device, gives the host preview's image", "[emulated]") {
  // prepare makes the adaptive preview on the host for a CPU render and leaves it to the
  // device for a GPU render (which may not read the field on the host): the two scales, and so
  // every pixel's count and sums, are the same bits; the device's preview draws its samples
  // (launches) without counting them, as the host's are not counted
  const std::vector<double> field = heat_field<double>(kN);
  tessera::SceneDesc s = heat_scene(kN, 8);
  s.image.spp = 64;
  s.image.target_error = 0.05;
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN);
  const tessera::PreparedScene on_host = tessera::prepare(view, s);
  s.options.device = tessera::Device::Cuda;
  const tessera::PreparedScene on_device = tessera::prepare(view, s);
  const auto b = tessera::cuda::emulated_backend();
  tessera::CudaTransfer tr_host, tr_device;
  tessera::RenderStats st_host, st_device;
  const tessera::Film a = render_on(b, on_host, &tr_host, &st_host);
  const tessera::Film c = render_on(b, on_device, &tr_device, &st_device);
  CHECK(same_bits(a, c));
  check_same_paths(st_host, st_device);
  CHECK(tr_device.launches > tr_host.launches);  // the preview's own launches
  // Some pixels took more than the pilot, some fewer than spp: the counts were decided
  std::uint64_t least = UINT64_MAX, most = 0;
  for (const tessera::PixelSums& p : c.pixels()) {
    least = std::min(least, p.n);
    most = std::max(most, p.n);
  }
  CHECK(least < most);
}

TEST_CASE("Emulated device: a deadline in the device's preview stops the render before any sample", "[emulated]") {
  // One preview sample per slice; after the first slice the test waits the deadline out: the
  // call says the deadline passed, and the image holds nothing (the preview's samples are not
  // the image's, and the pilot never ran)
  const std::vector<double> field = heat_field<double>(kN);
  const auto deadline = test_deadline();
  // (on the device, prepare leaves the preview to the render: eight slices of one sample)
  const tessera::PreparedScene ps = adaptive_heat(field, 9, tessera::Device::Cuda, deadline);
  const auto [film, st, tr] = render_cut_by_deadline(ps, deadline, 1);
  CHECK(tr.launches == 1);
  CHECK(st.samples == 0);
  bool empty = true;
  for (const tessera::PixelSums& p : film.pixels()) empty &= p.n == 0 && p.drawn == 0 && p.lum == 0.0;
  CHECK(empty);
}

namespace {

/// A film and counters rendered from device copies whose prepared scene is gone.
struct Detached {
  tessera::Film film;
  tessera::RenderStats stats;
};

/// Makes `ps`'s device copies on `b`, destroys `ps` (every host table prepare() made: majorants,
/// empty-space reach, axis tables, refinement tables, lights, background), calls `scribble` to
/// overwrite the caller's arrays, then runs the kernel over the copies alone, every pixel's
/// samples in one slice: any pointer of the device scene left pointing at host memory reads
/// freed memory (AddressSanitizer, in CI's sanitizer pass, stops there; elsewhere the counters
/// differ from the CPU's).
Detached render_detached(std::unique_ptr<tessera::PreparedScene> ps, const std::shared_ptr<DeviceBackend>& b,
                         const std::function<void()>& scribble) {
  using namespace tessera::cuda;
  const tessera::PreparedSceneImpl& s = tessera::prepared_scene_impl(*ps);
  const int w = s.desc.image.width, h = s.desc.image.height, spp = s.kernel.spp;
  auto ds = std::make_shared<DeviceScene>(s, b);
  ds->upload();
  ps.reset();
  scribble();
  std::vector<PixelJob> jobs;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) jobs.push_back({x, y, 0});
  const int lanes = sample_lanes(w, h, spp);
  const std::vector<tessera::PixelSums> px(jobs.size());
  std::array<unsigned long long, kCounterCount> counters{};
  BackendBuffer d_jobs(*b), d_px(*b), d_lanes(*b), d_counters(*b);
  d_jobs.upload(jobs.data(), jobs.size() * sizeof(PixelJob), "jobs");
  d_px.upload(px.data(), px.size() * sizeof(tessera::PixelSums), "sums");
  d_counters.upload(counters.data(), sizeof(counters), "counters");
  d_lanes.allocate(jobs.size() * lanes * sizeof(tessera::PixelSums), "lanes");
  b->zero(d_lanes.get(), d_lanes.bytes(), "lanes");
  const auto n = static_cast<std::int64_t>(jobs.size());
  BackendBuffer d_scratch(*b);  // the wavefront's path slots, when the backend's loop is the wavefront
  if (const std::size_t bytes = b->slice_scratch_bytes(ds->dispatch_scene(), n * lanes); bytes > 0)
    d_scratch.allocate(bytes, "path slots");
  const SliceArgs a{ds->kernel(),
                    ds->medium(),
                    d_jobs.as<PixelJob>(),
                    d_px.as<tessera::PixelSums>(),
                    d_lanes.as<tessera::PixelSums>(),
                    nullptr,
                    d_counters.as<unsigned long long>(),
                    0,
                    n,
                    0,
                    spp,
                    lanes,
                    nullptr,
                    nullptr,
                    d_scratch.get()};
  b->run_slice(ds->dispatch_scene(), a, 128, "detached slice");
  b->merge_lanes(d_px.as<tessera::PixelSums>(), nullptr, d_lanes.as<tessera::PixelSums>(), nullptr, n, lanes);
  Detached out{tessera::Film(w, h), {}};
  b->copy_to_host(out.film.pixels().data(), d_px.get(), px.size() * sizeof(tessera::PixelSums), "sums");
  b->copy_to_host(counters.data(), d_counters.get(), sizeof(counters), "counters");
  out.stats.samples = counters[kSamples];
  out.stats.real_collisions = counters[kRealCollisions];
  out.stats.null_collisions = counters[kNullCollisions];
  out.stats.free_flight_lookups = counters[kFreeFlightLookups];
  return out;
}

/// The CPU's render of ps against the detached device render of the same scene.
void check_detached(const char* what, const std::function<tessera::PreparedScene()>& prepare,
                    const std::function<void()>& scribble) {
  const tessera::PreparedScene ref = prepare();
  tessera::Film cpu(ref.desc().image.width, ref.desc().image.height);
  tessera::RenderStats cst;
  tessera::render(ref, cpu, cst);
  const Detached d =
      render_detached(std::make_unique<tessera::PreparedScene>(prepare()), tessera::cuda::emulated_backend(), scribble);
  INFO(what << ": real collisions " << d.stats.real_collisions << " (CPU " << cst.real_collisions << ")");
  CHECK(d.stats.samples == cst.samples);
  CHECK(d.stats.real_collisions == cst.real_collisions);
  CHECK(d.stats.null_collisions == cst.null_collisions);
  CHECK(d.stats.free_flight_lookups == cst.free_flight_lookups);
  CHECK(max_pixel_difference(cpu, d.film) < 1e-12);
}

}  // namespace

TEST_CASE("Emulated device: the device copies need nothing of the prepared scene or the caller's arrays",
          "[emulated]") {
  // A float32 field (widened) on rectilinear axes with a rect light and a gradient sky
  std::vector<float> field = heat_field<float>(kN);
  std::vector<double> x = stretched(kN, 1.3), y = stretched(kN, 0.9), z = stretched(kN, 1.0);
  check_detached(
      "rectilinear float32",
      [&] {
        tessera::SceneDesc s = heat_scene(kN, 21);
        s.geometry.coords[0] = x.data();
        s.geometry.coords[1] = y.data();
        s.geometry.coords[2] = z.data();
        return tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN), s);
      },
      [&] {
        std::fill(field.begin(), field.end(), 1.0e30f);
        std::fill(x.begin(), x.end(), -1.0e300);
        std::fill(y.begin(), y.end(), 1.0e300);
        std::fill(z.begin(), z.end(), 0.5);
      });
  // A vector's magnitude: three components of three dtypes
  std::vector<float> c0(field.size());
  std::vector<double> c1(field.size());
  std::vector<std::int16_t> c2(field.size());
  const std::vector<double> h = heat_field<double>(kN);
  for (std::size_t i = 0; i < h.size(); ++i) {
    c0[i] = static_cast<float>(0.6 * h[i]);
    c1[i] = 0.8 * h[i];
    c2[i] = static_cast<std::int16_t>(i % 7);
  }
  check_detached(
      "magnitude",
      [&] {
        tessera::MagnitudeField m;
        m.components[0] = FieldView::contiguous(c0.data(), tessera::DType::Float32, kN, kN, kN);
        m.components[1] = FieldView::contiguous(c1.data(), tessera::DType::Float64, kN, kN, kN);
        m.components[2] = FieldView::contiguous(c2.data(), tessera::DType::Int16, kN, kN, kN);
        return tessera::prepare(m, heat_scene(kN, 22));
      },
      [&] {
        std::fill(c0.begin(), c0.end(), 0.0f);
        std::fill(c1.begin(), c1.end(), 0.0);
        std::fill(c2.begin(), c2.end(), std::int16_t{-1});
      });
  // Two refinement levels of int16 cell data (stencil tables, candidate lists, patch addresses)
  constexpr std::int64_t n0 = 12;
  std::vector<std::int16_t> l0(static_cast<std::size_t>(n0 * n0 * n0)), l1(static_cast<std::size_t>(10 * 12 * 14));
  for (std::size_t i = 0; i < l0.size(); ++i) l0[i] = static_cast<std::int16_t>(300 + (i * 37) % 900);
  for (std::size_t i = 0; i < l1.size(); ++i) l1[i] = static_cast<std::int16_t>(300 + (i * 53) % 1000);
  check_detached(
      "refinement levels",
      [&] {
        std::vector<tessera::AmrPatch> patches(3);
        patches[0].view = FieldView::contiguous(l0.data(), tessera::DType::Int16, n0, n0, n0);
        // Two patches of level 1 side by side, the two parts of one 10 x 12 x 14 array (x 0-5
        // and 6-9): stencils across them use the candidate lists
        const std::int64_t nx[2] = {6, 4}, x0[2] = {4, 10};
        for (int p = 0; p < 2; ++p) {
          tessera::AmrPatch& q = patches[static_cast<std::size_t>(1 + p)];
          q.level = 1;
          q.offset[0] = x0[p];
          q.offset[1] = 6;
          q.offset[2] = 2;
          q.view = FieldView::contiguous(l1.data() + (p ? 6 : 0), tessera::DType::Int16, nx[p], 12, 14);
          q.view.byte_strides[1] = 10 * 2;
          q.view.byte_strides[2] = 10 * 12 * 2;
        }
        const tessera::AmrField amr = tessera_test::two_levels(tessera::DType::Int16, n0, patches);
        tessera::SceneDesc s = heat_scene(kN, 23);
        s.geometry.association = tessera::Association::Cell;
        s.geometry.spacing = Vec3(1.0 / n0);
        return tessera::prepare(amr, s, nullptr);
      },
      [&] {
        std::fill(l0.begin(), l0.end(), std::int16_t{-30000});
        std::fill(l1.begin(), l1.end(), std::int16_t{30000});
      });
  // An envmap background: its texels and sampling table live in the prepared scene (freed
  // before the render) and the image the scene was made from is overwritten
  std::shared_ptr<tessera::Image> sky = test_envmap(24, 12);
  const std::vector<double> hf = heat_field<double>(kN);
  check_detached(
      "envmap background",
      [&] {
        tessera::SceneDesc s = heat_scene(kN, 24);
        s.background = {};
        s.background.type = tessera::BackgroundType::EnvMap;
        s.background.envmap = sky;
        s.background.up = Vec3(0.3, 1.0, 0.0);
        return tessera::prepare(FieldView::contiguous(hf.data(), tessera::DType::Float64, kN, kN, kN), s);
      },
      [&] { std::fill(sky->rgba.begin(), sky->rgba.end(), 1.0e6f); });
  // A mesh of two domains: a curvilinear piece (x, y, z interleaved in one float32 array: one
  // copy) and tets (separate float64 coordinates, int64 indices), strided uint16 values; the
  // elements, boxes, location lists and domain readers live in the prepared scene
  std::vector<WarpedMeshPiece> pieces;
  pieces.emplace_back(14, 0, 6, MeshForm::Curvilinear, tessera::DType::UInt16, false);
  pieces.emplace_back(14, 6, 13, MeshForm::Tets, tessera::DType::UInt16, false, true);
  check_detached(
      "mesh", [&] { return tessera::prepare(mesh_of(pieces), heat_scene(14, 25)); },
      [&] {
        for (WarpedMeshPiece& p : pieces) p.scribble();
      });
}

TEST_CASE("Emulated device: a mesh's interleaved coordinates are copied once, device copies read in place",
          "[emulated][mesh]") {
  // Interleaved float32 coordinates: one span, one copy; device memory, or device copies the
  // caller names, read in place
  const std::vector<WarpedMeshPiece> curvi = {{12, 0, 11, MeshForm::Curvilinear, tessera::DType::Float32, false}};
  const tessera::Mesh mesh = mesh_of(curvi);
  const tessera::PreparedScene ps = tessera::prepare(mesh, heat_scene(12, 3));
  const tessera::MeshDomain& d = mesh.domains[0];
  const auto vertices = static_cast<std::uint64_t>(d.coords.count);
  const auto values = static_cast<std::uint64_t>(2 * d.field.count - 1) * sizeof(float);  // strided: 2 apart
  tessera::CudaTransfer tr;
  const tessera::Film a = render_on(tessera::cuda::emulated_backend(), ps, &tr);
  // In place: the coordinates and values in "device memory"
  EmulatedDevice dev;
  dev.device_ranges.emplace_back(d.coords.x, static_cast<std::size_t>(vertices * 3 * sizeof(float)));
  dev.device_ranges.emplace_back(d.field.data, static_cast<std::size_t>(values));
  const tessera::PreparedScene ps2 = tessera::prepare(mesh, heat_scene(12, 3));
  tessera::CudaTransfer in_place;
  const tessera::Film b = render_on(tessera::cuda::emulated_backend(dev), ps2, &in_place);
  CHECK_FALSE(tr.field_in_place);
  CHECK(in_place.field_in_place);
  CHECK(tr.bytes_to_device - in_place.bytes_to_device == vertices * 3 * sizeof(float) + values);
  CHECK(same_bits(a, b));
  // Host arrays with named device copies (MeshDomain::device_copy, as the adapter's staging
  // leaves them): the render reads the copies, never the host arrays, which are overwritten
  std::vector<WarpedMeshPiece> twin = {{12, 0, 11, MeshForm::Curvilinear, tessera::DType::Float32, false}};
  tessera::Mesh host_mesh = mesh_of(twin);
  EmulatedDevice dev2;
  dev2.device_ranges.emplace_back(d.coords.x, static_cast<std::size_t>(vertices * 3 * sizeof(float)));
  dev2.device_ranges.emplace_back(d.field.data, static_cast<std::size_t>(values));
  host_mesh.domains[0].device_copy[0] = d.coords.x;
  host_mesh.domains[0].device_copy[1] = d.coords.y;
  host_mesh.domains[0].device_copy[2] = d.coords.z;
  host_mesh.domains[0].device_copy[4] = d.field.data;
  const tessera::PreparedScene ps3 = tessera::prepare(host_mesh, heat_scene(12, 3));
  twin[0].scribble();
  tessera::CudaTransfer named;
  const tessera::Film c = render_on(tessera::cuda::emulated_backend(dev2), ps3, &named);
  CHECK(named.bytes_to_device == in_place.bytes_to_device);
  CHECK(same_bits(a, c));
}

namespace {

/// Bytes a device render copies of a mesh layout's tables (elements, boxes, location lists).
std::uint64_t table_bytes(const tessera::MeshLayout& layout) {
  const tessera::MeshFieldView v = layout.view(nullptr);
  const auto loc = static_cast<std::uint64_t>(v.loc_n[0] * v.loc_n[1] * v.loc_n[2]);
  return layout.element_count() * (sizeof(tessera::MeshElementRef) + 6 * sizeof(double)) +
         (loc + 1) * sizeof(std::uint64_t) + v.first[loc] * sizeof(std::uint32_t);
}

}  // namespace

TEST_CASE("Emulated device: a mesh's tables and geometry are copied once per layout and device, and go with the "
          "layout",
          "[emulated][mesh]") {
  // The layout (elements, boxes, location lists) is what later calls over an unchanged mesh
  // reuse: its device copy is kept with it, and the geometry's (coordinates, connectivity)
  // beside it, so their renders copy only the values
  const std::vector<WarpedMeshPiece> pieces = {{12, 0, 11, MeshForm::Hexes, tessera::DType::Float64, false}};
  const tessera::Mesh mesh = mesh_of(pieces);
  const auto b = tessera::cuda::emulated_backend();
  const auto other = tessera::cuda::emulated_backend();
  {
    const tessera::PreparedScene p1 = tessera::prepare(mesh, heat_scene(12, 3));
    const std::uint64_t kept = table_bytes(*p1.mesh_layout()) + geometry_bytes(mesh);
    tessera::CudaTransfer t1, t2, t3;
    const tessera::Film a = render_on(b, p1, &t1);
    const tessera::PreparedScene p2 = tessera::prepare(mesh, heat_scene(12, 3), p1.mesh_layout());
    REQUIRE(p2.mesh_layout_reused());
    const tessera::Film c = render_on(b, p2, &t2);
    CHECK(t1.bytes_to_device - t2.bytes_to_device == kept);
    CHECK(same_bits(a, c));
    // Another device: its own copy (the same bytes as the first render's)
    const tessera::Film d = render_on(other, p2, &t3);
    CHECK(t3.bytes_to_device == t1.bytes_to_device);
    CHECK(same_bits(a, d));
  }
  // The prepared scenes and the layout gone: nothing held on either device
  CHECK(tessera::cuda::emulated_bytes_held(*b) == 0);
  CHECK(tessera::cuda::emulated_bytes_held(*other) == 0);
}

TEST_CASE("Emulated device: a kept geometry copy serves arrays laid out alike, wherever they are, and no other",
          "[emulated][mesh]") {
  const auto b = tessera::cuda::emulated_backend();
  const std::vector<WarpedMeshPiece> pieces = {{12, 0, 7, MeshForm::Hexes, tessera::DType::Float64, false},
                                               {12, 7, 11, MeshForm::Curvilinear, tessera::DType::Float64, false}};
  const tessera::Mesh mesh = mesh_of(pieces);
  const tessera::PreparedScene p1 = tessera::prepare(mesh, heat_scene(12, 3));
  const std::uint64_t tables = table_bytes(*p1.mesh_layout());
  tessera::CudaTransfer t1;
  const tessera::Film a = render_on(b, p1, &t1);
  // The same geometry in other host arrays (the simulation's next buffers, or the arrays a
  // values-only exchange unpacks): the kept copy serves, and the render reads none of the
  // host geometry (overwritten after prepare): only the values are copied
  std::vector<WarpedMeshPiece> twin = pieces;
  const tessera::Mesh twin_mesh = mesh_of(twin);
  const tessera::PreparedScene p2 = tessera::prepare(twin_mesh, heat_scene(12, 3), p1.mesh_layout());
  REQUIRE(p2.mesh_layout_reused());
  for (WarpedMeshPiece& p : twin) p.scribble_geometry();
  tessera::CudaTransfer t2;
  const tessera::Film c = render_on(b, p2, &t2);
  CHECK(t1.bytes_to_device - t2.bytes_to_device == tables + geometry_bytes(mesh));
  CHECK(same_bits(a, c));
  // The same geometry laid out otherwise (the hexes' x, y, z interleaved: other spans, read
  // at another stride): the copy does not serve; the geometry is copied again (the tables
  // with it) and kept instead
  tessera::Mesh wide_mesh = mesh;
  tessera::MeshDomain& hexes = wide_mesh.domains[0];
  std::vector<double> xyz;
  for (std::int64_t v = 0; v < hexes.coords.count; ++v)
    for (const void* axis : {hexes.coords.x, hexes.coords.y, hexes.coords.z})
      xyz.push_back(static_cast<const double*>(axis)[v]);
  hexes.coords.x = xyz.data();
  hexes.coords.y = xyz.data() + 1;
  hexes.coords.z = xyz.data() + 2;
  hexes.coords.byte_stride = 3 * sizeof(double);
  const tessera::PreparedScene p3 = tessera::prepare(wide_mesh, heat_scene(12, 3), p1.mesh_layout());
  REQUIRE(p3.mesh_layout_reused());
  tessera::CudaTransfer t3, t4, t5;
  const tessera::Film d = render_on(b, p3, &t3);
  CHECK(t3.bytes_to_device == t2.bytes_to_device + tables + geometry_bytes(wide_mesh));
  CHECK(same_bits(a, d));
  // (each render below of a scene prepared anew, as each call's is)
  const tessera::PreparedScene p4 = tessera::prepare(wide_mesh, heat_scene(12, 3), p1.mesh_layout());
  const tessera::Film e = render_on(b, p4, &t4);  // now kept
  CHECK(t4.bytes_to_device == t2.bytes_to_device);
  CHECK(same_bits(a, e));
  const tessera::PreparedScene p5 = tessera::prepare(mesh, heat_scene(12, 3), p1.mesh_layout());
  const tessera::Film f = render_on(b, p5, &t5);  // the first arrays' layout again: copied again
  CHECK(t5.bytes_to_device == t1.bytes_to_device);
  CHECK(same_bits(a, f));
}
