// Distributed mode (insitu/src/mpi/parallel_context_mpi_paged.cpp, brick_service.cpp): no replica;
// each rank keeps its own block and fetches other ranks' bricks on first touch into a bounded
// cache. Asserted: over 2, 3 and 4 ranks (real and pretend nodes, 1 and 2 threads, even,
// uneven and 1-vertex-thick blocks, caches from 2 bricks to all of them) a render is
// bit-identical (every PixelSums byte, every counter) to a one-rank core render of the whole
// field, single and multiple scattering, with shadows crossing blocks and a light inside
// another rank's block; the global summary from per-rank parts equals the whole field's; no
// rank allocates a replica and the cache stays at its slots; several own domains per rank are
// read in place (none of their bricks becomes resident) with the replicated image; a rank that
// stops mid-render (its deadline) makes every rank fail, none hangs.
#include "mpi/parallel_context_mpi.h"

#include "mpi_render_support.h"
#include "mpi_test_support.h"

#include <tessera/byte_span.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>

using namespace tessera_mpi_test;
using tessera::Color;
using tessera::DType;
using tessera::Vec3;
using tessera::insitu::GlobalPlacement;
using tessera::insitu::MpiParallelContext;

namespace {

constexpr std::array<std::int64_t, 3> kGlobal{23, 19, 17};

GlobalPlacement placement(const Box& b) {
  GlobalPlacement p{};
  for (int a = 0; a < 3; ++a) {
    p.global_dims[a] = kGlobal[a];
    p.offset[a] = b.offset[a];
  }
  return p;
}

/// Even blocks of n ranks (split along i, j or i and k).
Box block(int n, int rank) {
  const std::array<int, 3> procs = n == 2   ? std::array<int, 3>{2, 1, 1}
                                   : n == 3 ? std::array<int, 3>{1, 3, 1}
                                            : std::array<int, 3>{2, 1, 2};
  return block_of(kGlobal, procs, rank);
}

/// Uneven slabs along i: rank 0 holds planes [0, 6), ranks 1..n-2 one plane each (1 vertex
/// thick), the last rank the rest.
Box uneven_block(int n, int rank) {
  Box b;
  b.dims = kGlobal;
  if (rank == 0) {
    b.offset[0] = 0;
    b.dims[0] = 6;
  } else if (rank < n - 1) {
    b.offset[0] = 5 + rank;
    b.dims[0] = 1;
  } else {
    b.offset[0] = 5 + rank;
    b.dims[0] = kGlobal[0] - b.offset[0];
  }
  return b;
}

/// Shadows from a rect light above and a sphere light inside the far corner of the field
/// (another rank's block), emission, hybrid shading.
tessera::SceneDesc scene_for(tessera::Scattering scattering, int threads) {
  tessera::SceneDesc s = base_scene(scattering, threads);
  s.camera.look_at = Vec3(0.55, 0.45, 0.4);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(0.95, 0.75, 0.65), 0.06, Color(8.0, 8.0, 12.0)});
  s.image = {41, 29, 2, 0.0};
  s.options.seed = 5;
  s.options.frame = 3;
  return s;
}

tessera::FieldView whole_view(const std::vector<unsigned char>& bytes) {
  return tessera::FieldView::contiguous(bytes.data(), DType::Float32, kGlobal[0], kGlobal[1], kGlobal[2]);
}

/// Prepares `scene` in distributed mode on every rank of ctx: distribute, summarize, prepare
/// while serving.
tessera::PreparedScene prepare_distributed(MpiParallelContext& ctx, const tessera::FieldView& local, const Box& box,
                                           const tessera::SceneDesc& scene, int shift, std::size_t capacity) {
  const tessera::PagedField paged = ctx.distribute(local, placement(box), shift, capacity);
  tessera::FieldView dims_only;
  for (int a = 0; a < 3; ++a) dims_only.dims[a] = kGlobal[a];
  const auto summary = ctx.summarize(local, placement(box), tessera::majorant_edge(dims_only, scene.integrator));
  tessera::PreparedScene prepared;
  ctx.serve_while([&] { prepared = tessera::prepare(paged, scene, summary); });
  return prepared;
}

}  // namespace

TEST_CASE("the global summary from every rank's part equals the whole field's", "[mpi][distributed]") {
  const auto value = blobs(kGlobal);
  const std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  for (int n : sizes_up_to_world()) {
    if (n < 2) continue;
    for (bool uneven : {false, true})
      for (int edge : {1, 4, 7, 64}) {
        FirstRanks sub(n);
        bool ok = true;
        if (sub.member()) {
          MpiParallelContext ctx(sub.comm(), 0);
          const Box box = uneven ? uneven_block(n, ctx.rank()) : block(n, ctx.rank());
          const LocalArray local(box, DType::Float32, Layout::MirroredJ, value);
          const auto s = ctx.summarize(local.view(), placement(box), edge);
          const tessera::FieldSummary ref(whole_view(global), edge);
          ok = s->cell_count() == ref.cell_count() && s->value_min() == ref.value_min() &&
               s->value_max() == ref.value_max() && s->nan_vertices() == ref.nan_vertices();
          for (std::int64_t c = 0; ok && c < ref.cell_count(); ++c) {
            const auto& x = s->ranges()[static_cast<std::size_t>(c)];
            const auto& y = ref.ranges()[static_cast<std::size_t>(c)];
            ok = std::memcmp(&x.lo, &y.lo, sizeof(double)) == 0 && std::memcmp(&x.hi, &y.hi, sizeof(double)) == 0 &&
                 x.nan == y.nan && x.pos_inf == y.pos_inf && x.neg_inf == y.neg_inf;
          }
        }
        INFO("ranks " << n << (uneven ? " uneven" : " even") << ", edge " << edge);
        REQUIRE(all_ranks(ok));
      }
  }
}

TEST_CASE("distributed renders are bit-identical to a one-rank render of the whole field",
          "[mpi][distributed][determinism]") {
  const auto value = blobs(kGlobal);
  const std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  for (const auto scattering : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    const tessera::SceneDesc ref_scene = scene_for(scattering, 2);
    const tessera::PreparedScene ref_prepared = tessera::prepare(whole_view(global), ref_scene);
    tessera::Film ref(ref_scene.image.width, ref_scene.image.height);
    tessera::RenderStats ref_stats;
    tessera::render(ref_prepared, ref, ref_stats);

    struct Variant {
      bool uneven;
      int ranks_per_node, threads, shift;
      std::size_t capacity;
    };
    const Variant variants[] = {
        {false, 0, 1, 3, 1000},  // every brick fits
        {false, 1, 2, 2, 3},     // pretend nodes, tiny cache: flushes
        {true, 0, 2, 3, 2},      // 1-vertex-thick blocks, two slots
        {true, 1, 1, 1, 64},     // bricks of 2 vertices
    };
    for (int n : sizes_up_to_world()) {
      if (n < 2) continue;
      for (const Variant& v : variants) {
        FirstRanks sub(n);
        bool ok = true;
        std::string what;
        if (sub.member()) {
          MpiParallelContext ctx(sub.comm(), v.ranks_per_node);
          const Box box = v.uneven ? uneven_block(n, ctx.rank()) : block(n, ctx.rank());
          const LocalArray local(box, DType::Float32, Layout::StructMember, value);
          const tessera::SceneDesc scene = scene_for(scattering, v.threads);
          const tessera::PreparedScene prepared =
              prepare_distributed(ctx, local.view(), box, scene, v.shift, v.capacity);
          tessera::Film film(scene.image.width, scene.image.height);
          tessera::RenderStats stats;
          ctx.render(prepared, film, stats);
          if (ctx.rank() == 0) {
            if (!same_pixels(film, ref)) ok = false, what += " pixels";
            if (!same_counters(stats, ref_stats)) ok = false, what += " counters";
          }
          // No replica, and the cache holds at most its slots
          const tessera::BrickGrid g = tessera::BrickGrid::make(kGlobal.data(), DType::Float32, v.shift);
          if (ctx.replica_bytes() != 0) ok = false, what += " replica";
          if (ctx.report().cache_bytes > tessera::BrickCache::bytes_for(g, v.capacity))
            ok = false, what += " cache bytes";
          if (ctx.report().cache.peak_resident > v.capacity) ok = false, what += " resident";
          // Some bricks did travel (each rank's rays cross other blocks)
          std::uint64_t got = ctx.report().bricks.bytes_received, all_got = 0;
          MPI_Allreduce(&got, &all_got, 1, MPI_UINT64_T, MPI_SUM, sub.comm());
          if (all_got == 0) ok = false, what += " no traffic";
        }
        INFO("scattering " << static_cast<int>(scattering) << ", ranks " << n << (v.uneven ? " uneven" : " even")
                           << ", ranks_per_node " << v.ranks_per_node << ", threads " << v.threads << ", shift "
                           << v.shift << ", capacity " << v.capacity << ":" << what);
        REQUIRE(all_ranks(ok));
      }
    }
  }
}

TEST_CASE("a rank that stops mid-render in distributed mode fails every rank and hangs none",
          "[mpi][distributed][errors]") {
  const auto value = blobs(kGlobal);
  MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  const int n = ctx.size();
  if (n < 2) return;
  const Box box = block(n, ctx.rank());
  const LocalArray local(box, DType::Float32, Layout::COrder, value);
  tessera::SceneDesc scene = scene_for(tessera::Scattering::Multiple, 1);
  if (ctx.rank() == n - 1) scene.options.deadline = std::chrono::steady_clock::now();  // already passed
  const tessera::PreparedScene prepared = prepare_distributed(ctx, local.view(), box, scene, 3, 4);
  tessera::Film film(scene.image.width, scene.image.height);
  tessera::RenderStats stats;
  bool threw = false;
  try {
    ctx.render(prepared, film, stats);
  } catch (const std::exception&) {
    threw = true;
  }
  REQUIRE(all_ranks(threw));
  // The context still works afterwards: the next distributed render is right
  const std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  const tessera::SceneDesc good = scene_for(tessera::Scattering::Single, 1);
  tessera::Film ref(good.image.width, good.image.height);
  tessera::RenderStats ref_stats;
  tessera::render(tessera::prepare(whole_view(global), good), ref, ref_stats);
  const tessera::PreparedScene again = prepare_distributed(ctx, local.view(), box, good, 3, 4);
  tessera::Film film2(good.image.width, good.image.height);
  ctx.render(again, film2, stats);
  REQUIRE(all_ranks(ctx.rank() != 0 || same_pixels(film2, ref)));
}

namespace {

/// `box` cut into three slabs along its longest axis at even global vertices (the in-place
/// table's cells are 2 vertices wide on this grid), the longest slab first.
std::vector<Box> three_slabs(const Box& box) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.dims[a] > box.dims[axis]) axis = a;
  const std::int64_t lo = box.offset[axis], len = box.dims[axis];
  const std::int64_t cuts[4] = {lo, (lo + len / 3) & ~std::int64_t{1}, (lo + 2 * len / 3) & ~std::int64_t{1}, lo + len};
  std::vector<Box> slabs;
  for (int s = 0; s < 3; ++s) {
    Box b = box;
    b.offset[axis] = cuts[s];
    b.dims[axis] = cuts[s + 1] - cuts[s];
    slabs.push_back(b);
  }
  std::stable_sort(slabs.begin(), slabs.end(), [&](const Box& a, const Box& b) { return a.dims[axis] > b.dims[axis]; });
  return slabs;
}

/// The one-rank core render of the whole field (what every distributed render must equal).
struct WholeRender {
  tessera::Film film;
  tessera::RenderStats stats;
  WholeRender(const std::vector<unsigned char>& global, const tessera::SceneDesc& scene)
      : film(scene.image.width, scene.image.height) {
    tessera::render(tessera::prepare(whole_view(global), scene), film, stats);
  }
};

/// The blobs as float32 under a multiple-scattering scene and its one-rank render.
struct BlobCase {
  decltype(blobs(kGlobal)) value = blobs(kGlobal);
  std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  tessera::SceneDesc scene = scene_for(tessera::Scattering::Multiple, 2);
  WholeRender whole{global, scene};
};

/// A rank's box as three slabs (three_slabs), each its own array in `layouts`' layout, and
/// their blocks in domain order.
struct SlabBlocks {
  std::vector<LocalArray> arrays;
  std::vector<tessera::insitu::FieldBlock> blocks;
  template <class Values>
  SlabBlocks(const Box& box, const Layout (&layouts)[3], const Values& value) {
    const std::vector<Box> slabs = three_slabs(box);
    for (std::size_t s = 0; s < slabs.size(); ++s) arrays.emplace_back(slabs[s], DType::Float32, layouts[s], value);
    for (std::size_t s = 0; s < slabs.size(); ++s) {
      tessera::insitu::FieldBlock& b = blocks.emplace_back();
      b.view = arrays[s].view();
      for (int a = 0; a < 3; ++a) b.offset[a] = slabs[s].offset[a];
      b.domain = static_cast<int>(s);
    }
  }
};

}  // namespace

TEST_CASE("several own domains per rank are read in place in distributed mode, bit for bit",
          "[mpi][distributed][domains][determinism]") {
  // Each rank's box as three slabs (own arrays, different layouts): the distributed render
  // equals the replicated one and a one-rank render of the whole field, and no brick that lies
  // wholly in this rank's slabs ever becomes resident in its cache (the own slabs are read in
  // place, not copied into slots), with a cache large enough never to evict
  const BlobCase blob;
  const auto& value = blob.value;
  const tessera::SceneDesc& scene = blob.scene;
  const tessera::Film& ref = blob.whole.film;
  const tessera::RenderStats& ref_stats = blob.whole.stats;
  constexpr int kShift = 2;
  const Layout layouts[3] = {Layout::StructMember, Layout::MirroredJ, Layout::FortranPadded};
  for (int n : sizes_up_to_world()) {
    if (n < 2) continue;
    FirstRanks sub(n);
    bool ok = true;
    std::string what;
    if (sub.member()) {
      MpiParallelContext ctx(sub.comm(), 0);
      const SlabBlocks slab_blocks(block(n, ctx.rank()), layouts, value);
      const std::vector<tessera::insitu::FieldBlock>& blocks = slab_blocks.blocks;
      tessera::FieldView dims_only;
      for (int a = 0; a < 3; ++a) dims_only.dims[a] = kGlobal[a];
      const int edge = tessera::majorant_edge(dims_only, scene.integrator);
      const tessera::BrickGrid g = tessera::BrickGrid::make(kGlobal.data(), DType::Float32, kShift);
      const auto capacity = static_cast<std::size_t>(g.brick_count());
      // Distributed
      const tessera::PagedField paged = ctx.distribute_blocks(blocks, kGlobal.data(), DType::Float32, kShift, capacity);
      const auto summary = ctx.summarize_blocks(blocks, kGlobal.data(), DType::Float32, edge);
      tessera::PreparedScene prepared;
      ctx.serve_while([&] { prepared = tessera::prepare(paged, scene, summary); });
      tessera::Film film(scene.image.width, scene.image.height);
      tessera::RenderStats stats;
      ctx.render(prepared, film, stats);
      if (ctx.rank() == 0 && !same_pixels(film, ref)) ok = false, what += " distributed pixels";
      if (ctx.rank() == 0 && !same_counters(stats, ref_stats)) ok = false, what += " distributed counters";
      if (paged.cache->in_place_count() != 2) ok = false, what += " in-place blocks";
      const Box mine = block(n, ctx.rank());
      std::int64_t own_bricks = 0, resident_own = 0;
      for (std::int64_t b = 0; b < g.brick_count(); ++b) {
        std::int64_t lo[3], hi[3];
        g.box(b, lo, hi);
        bool inside = true;
        for (int a = 0; a < 3; ++a)
          inside = inside && lo[a] >= mine.offset[a] && hi[a] <= mine.offset[a] + mine.dims[a];
        if (!inside) continue;
        ++own_bricks;
        if (paged.cache->find(b) != nullptr) ++resident_own;
      }
      if (own_bricks == 0) ok = false, what += " no own brick";
      if (resident_own != 0) ok = false, what += " " + std::to_string(resident_own) + " own bricks resident";
      if (ctx.report().cache.flushes != 0) ok = false, what += " flushed";
      if (ctx.report().cache.fetched == 0) ok = false, what += " nothing fetched";  // other ranks' bricks do travel
      // Replicated, from the same blocks
      const tessera::FieldView whole = ctx.assemble_blocks(blocks, kGlobal.data(), DType::Float32);
      const tessera::PreparedScene rp = tessera::prepare(whole, scene);
      tessera::Film rfilm(scene.image.width, scene.image.height);
      tessera::RenderStats rstats;
      ctx.render(rp, rfilm, rstats);
      if (ctx.rank() == 0 && !same_pixels(rfilm, film)) ok = false, what += " replicated != distributed";
    }
    INFO("ranks " << n << ":" << what);
    REQUIRE(all_ranks(ok));
  }
}

TEST_CASE("own domains in device memory are read through copies of their bricks in distributed mode, bit for bit",
          "[mpi][distributed][domains][device]") {
  // Each rank's box as three slabs, the first and the last marked device memory
  // (FieldBlock::on_device: what the adapter leaves on a GPU). The host reads them only
  // through cuda_copy_box_to_host and cuda_field_summary_accumulate (here, without a GPU,
  // gathers on the host): the summary, a CPU render whose own vertices come through the cache
  // and the other ranks' requests give the one-rank render's bits; the device blocks are not
  // in the in-place table, the first block is the device view's own block only, and the
  // bytes copied from them are counted.
  const BlobCase blob;
  const auto& value = blob.value;
  const tessera::SceneDesc& scene = blob.scene;
  const tessera::Film& ref = blob.whole.film;
  const tessera::RenderStats& ref_stats = blob.whole.stats;
  const Layout layouts[3] = {Layout::MirroredJ, Layout::StructMember, Layout::FortranPadded};
  for (int n : sizes_up_to_world()) {
    if (n < 2) continue;
    for (const int shift : {1, 2, 3}) {
      FirstRanks sub(n);
      bool ok = true;
      std::string what;
      if (sub.member()) {
        MpiParallelContext ctx(sub.comm(), 0);
        SlabBlocks slab_blocks(block(n, ctx.rank()), layouts, value);
        std::vector<tessera::insitu::FieldBlock>& blocks = slab_blocks.blocks;
        blocks[0].on_device = blocks[2].on_device = true;
        tessera::FieldView dims_only;
        for (int a = 0; a < 3; ++a) dims_only.dims[a] = kGlobal[a];
        const int edge = tessera::majorant_edge(dims_only, scene.integrator);
        const tessera::BrickGrid g = tessera::BrickGrid::make(kGlobal.data(), DType::Float32, shift);
        // A cache of a quarter of the bricks (evictions refetch own device bricks too), or with
        // the largest bricks of every brick: then each device part is copied once at most, and
        // the bytes copied stay within the device blocks'
        const bool all = shift == 3;
        const auto capacity =
            static_cast<std::size_t>(all ? g.brick_count() : std::max<std::int64_t>(8, g.brick_count() / 4));
        const std::uint64_t device_bytes =
            tessera::byte_span(blocks[0].view).bytes() + tessera::byte_span(blocks[2].view).bytes();
        const tessera::PagedField paged =
            ctx.distribute_blocks(blocks, kGlobal.data(), DType::Float32, shift, capacity);
        const auto summary = ctx.summarize_blocks(blocks, kGlobal.data(), DType::Float32, edge);
        if (!paged.local_device_only || paged.local_device != blocks[0].view.data)
          ok = false, what += " first block not device-only";
        if (paged.cache->in_place_count() != 1) ok = false, what += " in-place blocks";
        // The summary equals the host blocks' one
        std::vector<tessera::insitu::FieldBlock> host_blocks = blocks;
        for (auto& b : host_blocks) b.on_device = false;
        const auto host_summary = ctx.summarize_blocks(host_blocks, kGlobal.data(), DType::Float32, edge);
        for (std::size_t c = 0; c < summary->ranges().size(); ++c) {
          const tessera::CellRange a = summary->ranges()[c], b = host_summary->ranges()[c];
          if (std::memcmp(&a.lo, &b.lo, sizeof a.lo) != 0 || std::memcmp(&a.hi, &b.hi, sizeof a.hi) != 0)
            ok = false, what += " summary cell " + std::to_string(c);
        }
        tessera::PreparedScene prepared;
        ctx.serve_while([&] { prepared = tessera::prepare(paged, scene, summary); });
        tessera::Film film(scene.image.width, scene.image.height);
        tessera::RenderStats stats;
        ctx.render(prepared, film, stats);
        if (ctx.rank() == 0 && !same_pixels(film, ref)) ok = false, what += " pixels";
        if (ctx.rank() == 0 && !same_counters(stats, ref_stats)) ok = false, what += " counters";
        if (ctx.report().bricks.bytes_from_device == 0) ok = false, what += " nothing copied from the device";
        if (ctx.paged_bytes_from_device() != ctx.report().bricks.bytes_from_device) ok = false, what += " bytes";
        if (all && ctx.report().bricks.bytes_from_device > device_bytes)
          ok = false, what += " " + std::to_string(ctx.report().bricks.bytes_from_device) +
                              " bytes copied, the device "
                              "blocks hold " +
                              std::to_string(device_bytes);
      }
      INFO("ranks " << n << ", shift " << shift << ":" << what);
      REQUIRE(all_ranks(ok));
    }
  }
}
