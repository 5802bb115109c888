// Distributed (paged) fields on the GPU (cuda/device_bricks.h): the device renders a field no
// rank holds whole by replaying launches that missed a brick, so the image is the bits of the
// same scene rendered on the device from the whole field, whatever the own block, the pool
// and the launch configuration; counters too (a discarded launch's are restored). A pool too
// small for one path, and a rank's service failing, end the call with a named error, and the
// next call renders. Runs on a CUDA device (label gpu) and on the host emulation (every build).
#include "gpu_test_util.h"
#include "two_levels.h"

#include "../core/fake_brick_service.h"

#if defined(TESSERA_GPU_TESTS_EMULATED)
#include "cuda/device_render.h"
#include "cuda/emulated_device.h"
#endif

#include <tessera/amr.h>
#include <tessera/brick_cache.h>
#include <tessera/field_summary.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using namespace gpu_test;

namespace {

constexpr int kN = 20;

/// The heat field of `dtype` (integers: scaled into their range) as bytes.
std::vector<unsigned char> heat_bytes(tessera::DType dtype, int n) {
  const std::vector<double> v = heat_field<double>(n);
  const std::size_t es = tessera::dtype_size(dtype);
  std::vector<unsigned char> out(v.size() * es);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double x = dtype == tessera::DType::UInt8    ? v[i] / 6.0
                     : dtype == tessera::DType::Int16  ? v[i] * 10.0 - 6000.0
                     : dtype == tessera::DType::UInt16 ? v[i] * 40.0
                                                       : v[i];
    tessera::detail::store_from_double(dtype, out.data() + i * es, x);
  }
  return out;
}

/// The heat scene with its TF range over the dtype's scaled values, a small image.
tessera::SceneDesc scene_for(tessera::DType dtype, std::uint64_t seed) {
  tessera::SceneDesc s = heat_scene(kN, seed);
  switch (dtype) {
    case tessera::DType::UInt8: s.tf.lo = 50.0, s.tf.hi = 216.0; break;
    case tessera::DType::Int16: s.tf.lo = -3000.0, s.tf.hi = 7000.0; break;
    case tessera::DType::UInt16: s.tf.lo = 12000.0, s.tf.hi = 52000.0; break;
    default: break;
  }
  s.image = {24, 20, 8, 0.0};
  s.options.tile = 8;
  return s;
}

/// A distributed field over `whole`: this rank holds vertices k < own_k (none when 0), the
/// rest served brick by brick (2^shift vertices) into a host cache of `host_slots`.
struct Distributed {
  tessera::BrickCache cache;
  tessera::PagedField field;
  Distributed(const FieldView& whole, int shift, std::size_t host_slots, std::int64_t own_k)
      : cache(tessera::BrickGrid::make(whole.dims, whole.dtype, shift), host_slots) {
    field.dtype = whole.dtype;
    for (int a = 0; a < 3; ++a) field.dims[a] = whole.dims[a];
    field.local.dtype = whole.dtype;
    if (own_k > 0) {
      field.local = whole;
      field.local.dims[2] = own_k;
    }
    field.cache = &cache;
  }
};

std::shared_ptr<const tessera::FieldSummary> summary_of(const FieldView& whole, const tessera::SceneDesc& s) {
  const int edge = tessera::majorant_edge(whole, s.integrator);
  const std::int64_t origin[3] = {0, 0, 0};
  return tessera::FieldSummary::from_parts(tessera::FieldSummary::partial(whole, origin, whole.dims, edge), {}, edge);
}

struct Rendered {
  tessera::Film film{1, 1};
  tessera::RenderStats stats;
  tessera::CudaTransfer transfer;
};

/// The distributed field rendered on the device, its bricks served from `whole`.
Rendered render_distributed(const FieldView& whole, const tessera::SceneDesc& s, int shift, std::size_t host_slots,
                            std::int64_t own_k, const tessera::CudaLaunch& launch = {}) {
  Distributed d(whole, shift, host_slots, own_k);
  tessera_test::FakeBrickService service(d.cache, whole);
  const tessera::PreparedScene ps = tessera::prepare(d.field, s, summary_of(whole, s));
  Rendered r;
  r.film = render_gpu(ps, launch, &r.transfer, &r.stats);
  REQUIRE_FALSE(d.cache.failed());
  return r;
}

}  // namespace

TEST_CASE("GPU: a distributed field renders the whole field's bits on the device", "[gpu][paged]") {
  for (const tessera::DType dtype :
       {tessera::DType::UInt8, tessera::DType::Int16, tessera::DType::Float32, tessera::DType::Float64}) {
    INFO("dtype " << tessera::dtype_name(dtype));
    const std::vector<unsigned char> bytes = heat_bytes(dtype, kN);
    const FieldView whole = FieldView::contiguous(bytes.data(), dtype, kN, kN, kN);
    const tessera::SceneDesc s = scene_for(dtype, 11);
    tessera::RenderStats ref_stats;
    const tessera::Film ref = render_gpu(tessera::prepare(whole, s), {}, nullptr, &ref_stats);
    REQUIRE(ref_stats.samples > 0);
    // Own block the lower half; host cache of every brick: the device's pool holds them all,
    // so each brick crosses once
    const Rendered all = render_distributed(whole, s, 2, 125, kN / 2);
    CHECK(same_bits(all.film, ref));
    check_same_paths(all.stats, ref_stats);
    CHECK(all.transfer.replays > 0);
    CHECK(all.transfer.bricks > 0);
    // (the own block is read on the device: the 50 bricks wholly inside it never come)
    CHECK(all.transfer.bricks <= 75);
    // No own block and a pool of 60 bricks (4^3 vertices): launches split and bricks evicted
    // and fetched again, the same bits
    const Rendered few = render_distributed(whole, s, 2, 60, 0);
    CHECK(same_bits(few.film, ref));
    check_same_paths(few.stats, ref_stats);
    CHECK(few.transfer.bricks > all.transfer.bricks);
    CHECK(few.transfer.launches > all.transfer.launches);
  }
}

TEST_CASE("GPU: a distributed field's image does not depend on the launches or the brick size", "[gpu][paged]") {
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::UInt16, kN);
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::UInt16, kN, kN, kN);
  tessera::SceneDesc s = scene_for(tessera::DType::UInt16, 3);
  const tessera::Film ref = render_gpu(tessera::prepare(whole, s));
  tessera::CudaLaunch small;
  small.samples_per_launch = 3;
  small.pixels_per_launch = 50;
  small.block_threads = 64;
  CHECK(same_bits(render_distributed(whole, s, 3, 27, 7, small).film, ref));
  CHECK(same_bits(render_distributed(whole, s, 1, 400, 0).film, ref));
  // Rectilinear axes: the same bits as the whole field's
  std::vector<double> x = stretched(kN, 1.3), y = stretched(kN, 0.8), z = stretched(kN, 1.0);
  s.geometry.coords[0] = x.data();
  s.geometry.coords[1] = y.data();
  s.geometry.coords[2] = z.data();
  const tessera::Film rect = render_gpu(tessera::prepare(whole, s));
  CHECK(same_bits(render_distributed(whole, s, 2, 70, 5).film, rect));
}

TEST_CASE("GPU: adaptive sampling over a distributed field gives the whole field's counts and bits", "[gpu][paged]") {
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::Float64, kN);
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::Float64, kN, kN, kN);
  tessera::SceneDesc s = scene_for(tessera::DType::Float64, 8);
  s.image.spp = 24;
  s.image.target_error = 0.05;
  tessera::RenderStats ref_stats;
  const tessera::Film ref = render_gpu(tessera::prepare(whole, s), {}, nullptr, &ref_stats);
  const Rendered r = render_distributed(whole, s, 2, 70, 4);
  CHECK(same_bits(r.film, ref));
  check_same_paths(r.stats, ref_stats);
}

TEST_CASE("GPU: a distributed field whose path needs more bricks than the pool fails by name, then renders",
          "[gpu][paged]") {
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::Float64, kN);
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::Float64, kN, kN, kN);
  const tessera::SceneDesc s = scene_for(tessera::DType::Float64, 2);
  {
    // One slot of 2^3 vertices: a camera ray crosses several bricks
    Distributed d(whole, 1, 1, 0);
    tessera_test::FakeBrickService service(d.cache, whole);
    const tessera::PreparedScene ps = tessera::prepare(d.field, s, summary_of(whole, s));
    tessera::Film film(s.image.width, s.image.height);
    tessera::RenderStats st;
    CHECK_THROWS_WITH(gpu_render_tiles(ps, all_tiles(ps), film, st),
                      Catch::Contains("needs more bricks at once than the device's pool of 1") &&
                          Catch::Contains("brick_cache") && Catch::Contains("one sample's path (pixel ("));
  }
  {
    // The service fails (another rank's brick cannot come): the call fails naming it; the
    // same prepared scene renders on the next call once the bricks come again
    Distributed d(whole, 2, 125, 0);
    const tessera::PreparedScene ps = tessera::prepare(d.field, s, summary_of(whole, s));
    tessera::Film film(s.image.width, s.image.height);
    tessera::RenderStats st;
    {
      tessera_test::FakeBrickService failing(d.cache, whole, 3);
      CHECK_THROWS_WITH(gpu_render_tiles(ps, all_tiles(ps), film, st), Catch::Contains("fake service: failing"));
    }
    d.cache.reset();
    tessera_test::FakeBrickService service(d.cache, whole);
    tessera::Film again(s.image.width, s.image.height);
    tessera::RenderStats st2;
    gpu_render_tiles(ps, all_tiles(ps), again, st2);
    CHECK(same_bits(again, render_gpu(tessera::prepare(whole, s))));
  }
}

TEST_CASE("GPU: a distributed field's pool stays within the memory limit", "[gpu][paged]") {
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::Float64, kN);
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::Float64, kN, kN, kN);
  const tessera::SceneDesc s = scene_for(tessera::DType::Float64, 4);
  const tessera::Film ref = render_gpu(tessera::prepare(whole, s));
  // Every brick would take 125 slots of 512 bytes; the limit leaves room for about 85
  tessera::CudaLaunch launch;
  const Rendered free = render_distributed(whole, s, 2, 125, 0);
  launch.memory_limit_bytes = free.transfer.device_bytes - 40 * 512;
  const Rendered bounded = render_distributed(whole, s, 2, 125, 0, launch);
  CHECK(bounded.transfer.device_bytes <= launch.memory_limit_bytes);
  CHECK(same_bits(bounded.film, ref));
  CHECK(bounded.transfer.bricks > free.transfer.bricks);  // fewer slots: some fetched again
}

TEST_CASE("GPU: a distributed hierarchy of refinement levels is refused by name", "[gpu][paged]") {
  // Two levels, every patch held here but read through a brick cache (distributed mode): not
  // on the device yet
  const std::int64_t n0 = 8, fine[3] = {8, 8, 8}, at0[3] = {0, 0, 0}, at1[3] = {4, 4, 4};
  const std::int64_t d0[3] = {n0, n0, n0};
  std::vector<double> v0(static_cast<std::size_t>(n0 * n0 * n0), 1.0), v1(512, 2.0);
  const tessera::AmrPatch patches[2] = {
      tessera_test::contiguous_patch(0, at0, v0.data(), tessera::DType::Float64, d0),
      tessera_test::contiguous_patch(1, at1, v1.data(), tessera::DType::Float64, fine)};
  tessera::AmrField amr = tessera_test::two_levels(tessera::DType::Float64, n0, patches);
  std::vector<tessera::AmrBox> boxes(2);
  for (int i = 0; i < 2; ++i) {
    boxes[i].level = patches[i].level;
    for (int a = 0; a < 3; ++a) {
      boxes[i].offset[a] = patches[i].offset[a];
      boxes[i].dims[a] = patches[i].view.dims[a];
    }
  }
  amr.layout = tessera::amr_virtual_layout(amr, tessera::Association::Cell, boxes, 2);
  tessera::BrickCache cache(tessera::BrickGrid::make(amr.layout.dims, tessera::DType::Float64, 2), 4);
  amr.cache = &cache;
  tessera::SceneDesc s = heat_scene(9, 1);
  s.geometry.association = tessera::Association::Cell;
  s.tf.lo = 0.0;
  s.tf.hi = 3.0;
  s.image = {16, 16, 2, 0.0};
  const int edge =
      tessera::majorant_edge(FieldView::contiguous(nullptr, tessera::DType::Float64, n0, n0, n0), s.integrator);
  tessera::AmrField held = amr;  // the summary of every patch (all are held here)
  held.cache = nullptr;
  const tessera::PreparedScene ps =
      tessera::prepare(amr, s, tessera::amr_summary(held, tessera::Association::Cell, edge));
  tessera::Film film(16, 16);
  tessera::RenderStats st;
  CHECK_THROWS_WITH(gpu_render_tiles(ps, all_tiles(ps), film, st),
                    Catch::Contains("distributed (paged) hierarchy of refinement levels") &&
                        Catch::Contains("not supported on the GPU"));
  CHECK(st.samples == 0);
}

#if defined(TESSERA_GPU_TESTS_EMULATED)
TEST_CASE("Emulated device: a distributed field's own block in device memory is read in place", "[emulated][paged]") {
  // The own block (k < 10) as the adapter hands it: a host copy in `local`, the simulation's
  // device array in `local_device`. Read there: the same bits, exactly its bytes fewer to
  // the device than when the host copy is copied over
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::Float64, kN);
  std::vector<unsigned char> on_device = bytes;
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::Float64, kN, kN, kN);
  const tessera::SceneDesc s = scene_for(tessera::DType::Float64, 9);
  const auto render = [&](const void* local_device, tessera::CudaTransfer& tr) {
    Distributed d(whole, 2, 125, kN / 2);
    d.field.local_device = local_device;
    tessera_test::FakeBrickService service(d.cache, whole);
    const tessera::PreparedScene ps = tessera::prepare(d.field, s, summary_of(whole, s));
    return render_gpu(ps, {}, &tr);
  };
  tessera::CudaTransfer copied, in_place;
  const tessera::Film a = render(nullptr, copied);
  tessera::cuda::emulated_declare_device_memory(*emulated_gpu(), on_device.data(), on_device.size());
  const tessera::Film b = render(on_device.data(), in_place);
  tessera::cuda::emulated_forget_device_memory(*emulated_gpu(), on_device.data());
  CHECK(same_bits(a, b));
  CHECK(copied.bytes_to_device - in_place.bytes_to_device == std::uint64_t{kN * kN * (kN / 2) * 8});
  CHECK(copied.bricks == in_place.bricks);
  // A device copy the caller names but that is host memory is not trusted: copied as before
  tessera::CudaTransfer host_named;
  CHECK(same_bits(a, render(on_device.data(), host_named)));
  CHECK(host_named.bytes_to_device == copied.bytes_to_device);
}

TEST_CASE("Emulated device: a deadline between replays keeps only whole launches of a distributed field",
          "[emulated][paged]") {
  // One sample per launch: the first launch misses the bricks it reaches, is discarded and run
  // again; the deadline passes after the fourth launch. The film holds the samples of the
  // launches that missed nothing, whole: every pixel the same count, the counters theirs
  const std::vector<unsigned char> bytes = heat_bytes(tessera::DType::Float64, kN);
  const FieldView whole = FieldView::contiguous(bytes.data(), tessera::DType::Float64, kN, kN, kN);
  tessera::SceneDesc s = scene_for(tessera::DType::Float64, 6);
  const auto deadline = test_deadline();
  s.options.deadline = deadline;
  Distributed d(whole, 2, 125, 0);
  tessera_test::FakeBrickService service(d.cache, whole);
  const tessera::PreparedScene ps = tessera::prepare(d.field, s, summary_of(whole, s));
  const auto [film, st, tr] = render_cut_by_deadline(ps, deadline, 4);
  CHECK(tr.launches == 4);
  CHECK(tr.replays >= 1);
  const std::uint64_t kept = film.pixels()[0].drawn;
  CHECK(kept == static_cast<std::uint64_t>(4 - tr.replays));
  bool same = true;
  for (const tessera::PixelSums& p : film.pixels()) same &= p.drawn == kept;
  CHECK(same);
  CHECK(st.samples == kept * static_cast<std::uint64_t>(s.image.width * s.image.height));
}
#endif
