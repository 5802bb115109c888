// MpiParallelContext (insitu/src/mpi/parallel_context_mpi.cpp): assembly of strided local views
// into one shared replica per node, dynamic tile distribution and the gather on rank 0.
// Physics asserted: the replica is the global field exactly; a render over 1, 2, 3 or 4 ranks
// is bit-identical (every PixelSums byte, every counter) to a one-rank core render.
#include "mpi/parallel_context_mpi.h"

#include "mpi_render_support.h"
#include "mpi_test_support.h"

#include <algorithm>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

using namespace tessera_mpi_test;
using tessera::Color;
using tessera::DType;
using tessera::Vec3;
using tessera::insitu::GlobalPlacement;
using tessera::insitu::MpiParallelContext;

namespace {

constexpr std::array<std::int64_t, 3> kGlobal{23, 19, 17};

/// Ranks along i, j, k for n ranks: splits along i (the fastest axis) too.
std::array<int, 3> procs_for(int n) {
  switch (n) {
    case 1: return {1, 1, 1};
    case 2: return {2, 1, 1};
    case 3: return {1, 3, 1};
    default: return {2, 1, 2};
  }
}

GlobalPlacement placement(const Box& b, const std::array<std::int64_t, 3>& g) {
  GlobalPlacement p{};
  for (int a = 0; a < 3; ++a) {
    p.global_dims[a] = g[a];
    p.offset[a] = b.offset[a];
  }
  return p;
}

/// Heterogeneous field, hybrid shading, emission, both light kinds and a gradient background;
/// the volume sits in the left part of the image so that many tiles are empty.
tessera::SceneDesc scene_for(tessera::Scattering scattering, int threads) {
  tessera::SceneDesc s = base_scene(scattering, threads);
  s.camera.look_at = Vec3(1.1, 0.0, 0.4);
  s.lights.push_back(tessera::SphereLightDesc{Vec3(-1.5, 0.5, 1.0), 0.3, Color(3.0, 3.0, 6.0)});
  s.image = {61, 45, 3, 0.0};  // partial tiles on the right and bottom
  s.options.seed = 99;
  s.options.frame = 7;
  return s;
}

/// Every vertex of `v` (read through its strides) equals the C-order bytes `expect`.
bool holds(const tessera::FieldView& v, const std::vector<unsigned char>& expect) {
  const std::size_t e = tessera::dtype_size(v.dtype);
  if (static_cast<std::size_t>(v.vertex_count()) * e != expect.size()) return false;
  const auto* base = static_cast<const unsigned char*>(v.data);
  std::size_t n = 0;
  for (std::int64_t k = 0; k < v.dims[2]; ++k)
    for (std::int64_t j = 0; j < v.dims[1]; ++j)
      for (std::int64_t i = 0; i < v.dims[0]; ++i, ++n)
        if (std::memcmp(base + i * v.byte_strides[0] + j * v.byte_strides[1] + k * v.byte_strides[2],
                        expect.data() + n * e, e) != 0)
          return false;
  return true;
}

}  // namespace

TEST_CASE("assemble copies every layout and dtype into one C-order replica per node", "[mpi][assemble]") {
  struct Variant {
    Layout layout;
    DType dtype;
  };
  const Variant variants[] = {{Layout::COrder, DType::Float32},
                              {Layout::FortranPadded, DType::UInt8},
                              {Layout::MirroredJ, DType::Float64},
                              {Layout::StructMember, DType::Float64},
                              {Layout::COrder, DType::Int16}};
  const auto value = blobs(kGlobal);
  for (int n : sizes_up_to_world())
    for (int ranks_per_node : {0, 1}) {  // 1: every rank its own node, the inter-node path
      FirstRanks sub(n);
      bool ok = true;
      std::string what;
      if (sub.member()) {
        MpiParallelContext ctx(sub.comm(), ranks_per_node);
        const Box box = block_of(kGlobal, procs_for(n), ctx.rank());
        for (const Variant& v : variants) {
          const LocalArray local(box, v.dtype, v.layout, value);
          const tessera::FieldView view = local.view();
          const tessera::FieldView whole = ctx.assemble(view, placement(box, kGlobal));
          const std::vector<unsigned char> expect = global_bytes(kGlobal, v.dtype, value);
          bool good = whole.dtype == v.dtype && whole.dims[0] == kGlobal[0] && whole.dims[1] == kGlobal[1] &&
                      whole.dims[2] == kGlobal[2] && holds(whole, expect);
          if (n == 1) {
            good = good && whole.data == view.data;  // one rank: zero copy
          } else {                                   // the replica is dense C order
            good = good && std::memcmp(whole.data, expect.data(), expect.size()) == 0;
          }
          // The window is reused while the size stays.
          if (n > 1) {
            const tessera::FieldView again = ctx.assemble(view, placement(box, kGlobal));
            good = good && again.data == whole.data && ctx.replica_bytes() == expect.size();
          }
          if (!good) {
            ok = false;
            what += " layout " + std::to_string(static_cast<int>(v.layout)) + " dtype " + tessera::dtype_name(v.dtype);
          }
        }
        if (n > 1 && ranks_per_node == 1 && ctx.node_count() != n) {
          ok = false;
          what += " node count " + std::to_string(ctx.node_count());
        }
      }
      INFO("ranks " << n << ", ranks_per_node " << ranks_per_node << ":" << what);
      REQUIRE(all_ranks(ok));
    }
}

TEST_CASE("renders over 1, 2, 3 and 4 ranks are bit-identical to a one-rank render", "[mpi][render][determinism]") {
  const auto value = blobs(kGlobal);
  const std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  const tessera::FieldView whole =
      tessera::FieldView::contiguous(global.data(), DType::Float32, kGlobal[0], kGlobal[1], kGlobal[2]);
  for (const auto scattering : {tessera::Scattering::Single, tessera::Scattering::Multiple}) {
    // The reference: core alone, one call, all tiles, twice into the same film (progressive).
    const tessera::SceneDesc ref_scene = scene_for(scattering, 2);
    const tessera::PreparedScene ref_prepared = tessera::prepare(whole, ref_scene);
    // image.denoise's auxiliary sums travel with the pixels: with them for multiple scattering
    const bool aux = scattering == tessera::Scattering::Multiple;
    tessera::Film ref_once(ref_scene.image.width, ref_scene.image.height, aux);
    tessera::RenderStats ref_stats;
    tessera::render(ref_prepared, ref_once, ref_stats);
    tessera::Film ref_twice = ref_once;
    tessera::RenderStats unused;
    tessera::render(ref_prepared, ref_twice, unused);

    for (int n : sizes_up_to_world())
      for (int ranks_per_node : {0, 1})
        for (int threads : {1, 2}) {
          FirstRanks sub(n);
          bool ok = true;
          std::string what;
          if (sub.member()) {
            MpiParallelContext ctx(sub.comm(), ranks_per_node);
            const Box box = block_of(kGlobal, procs_for(n), ctx.rank());
            const LocalArray local(box, DType::Float32, Layout::MirroredJ, value);
            const tessera::FieldView replica = ctx.assemble(local.view(), placement(box, kGlobal));
            const tessera::PreparedScene prepared = tessera::prepare(replica, scene_for(scattering, threads));
            tessera::Film film(ref_scene.image.width, ref_scene.image.height, aux);
            tessera::RenderStats stats;
            ctx.render(prepared, film, stats);
            // Every tile rendered exactly once across the ranks.
            int tiles = ctx.report().tiles, all_tiles = 0;
            MPI_Allreduce(&tiles, &all_tiles, 1, MPI_INT, MPI_SUM, sub.comm());
            if (all_tiles != static_cast<int>(prepared.tiles().size())) ok = false, what += " tile count";
            if (ctx.rank() == 0) {
              if (!same_pixels(film, ref_once)) ok = false, what += " pixels";
              if (!same_counters(stats, ref_stats)) ok = false, what += " counters";
            }
            // A second render continues every pixel's sample sequence.
            ctx.render(prepared, film, stats);
            if (ctx.rank() == 0 && !same_pixels(film, ref_twice)) ok = false, what += " progressive pixels";
            if (n > 1 && ctx.bytes_moved() == 0) ok = false, what += " bytes_moved";
          }
          INFO("scattering " << static_cast<int>(scattering) << ", ranks " << n << ", ranks_per_node " << ranks_per_node
                             << ", threads " << threads << ":" << what);
          REQUIRE(all_ranks(ok));
        }
  }
}

TEST_CASE("agree, any, min and range reduce over all ranks", "[mpi]") {
  MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  const int r = ctx.rank(), n = ctx.size();
  REQUIRE(ctx.agree(true));
  REQUIRE(ctx.agree(r != n - 1) == false);
  REQUIRE(ctx.any(false) == false);
  REQUIRE(ctx.any(r == n - 1));
  REQUIRE(ctx.min(7 - r) == 7 - (n - 1));
  REQUIRE(ctx.min(-3) == -3);
  const auto [lo, hi] = ctx.range(10.0 + r, 20.0 + r);
  REQUIRE(lo == 10.0);
  REQUIRE(hi == 20.0 + (n - 1));
}

TEST_CASE("a bad field or decomposition on one rank fails on every rank, and none hangs", "[mpi][errors]") {
  MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  const int r = ctx.rank(), n = ctx.size(), last = n - 1;
  const auto value = blobs(kGlobal);
  const Box box = block_of(kGlobal, procs_for(n), r);
  const LocalArray local(box, DType::Float32, Layout::COrder, value);

  const auto fails_everywhere = [&](const tessera::FieldView& view, const GlobalPlacement& where) {
    bool threw = false;
    try {
      ctx.assemble(view, where);
    } catch (const std::runtime_error&) {
      threw = true;
    } catch (const std::invalid_argument&) {
      threw = true;  // one rank: the view's own validation
    }
    return all_ranks(threw);
  };

  SECTION("null data on the last rank") {
    tessera::FieldView v = local.view();
    if (r == last) v.data = nullptr;
    REQUIRE(fails_everywhere(v, placement(box, kGlobal)));
  }
  SECTION("the last rank's box is shifted: overlap (or, on one rank, leaves the grid)") {
    GlobalPlacement p = placement(box, kGlobal);
    if (r == last) p.offset[0] = box.offset[0] == 0 ? 1 : box.offset[0] - 1;
    REQUIRE(fails_everywhere(local.view(), p));
  }
  SECTION("the last rank publishes one plane too few: a hole") {
    tessera::FieldView v = local.view();
    if (r == last) v.dims[2] -= 1;
    if (v.dims[2] >= 1) REQUIRE(fails_everywhere(v, placement(box, kGlobal)));
  }
  SECTION("the last rank publishes another dtype or global size") {
    tessera::FieldView v = local.view();
    GlobalPlacement p = placement(box, kGlobal);
    if (r == last) p.global_dims[1] += 1;
    REQUIRE(fails_everywhere(v, p));
    if (n > 1) {
      if (r == last) v.dtype = DType::UInt16;
      REQUIRE(fails_everywhere(v, placement(box, kGlobal)));
    }
  }
  SECTION("rank 0's film has the wrong size") {
    const tessera::FieldView replica = ctx.assemble(local.view(), placement(box, kGlobal));
    const tessera::PreparedScene prepared = tessera::prepare(replica, scene_for(tessera::Scattering::Single, 1));
    tessera::Film film = r == 0 ? tessera::Film(3, 3) : tessera::Film(61, 45);
    tessera::RenderStats stats;
    bool threw = false;
    try {
      ctx.render(prepared, film, stats);
    } catch (const std::exception&) {
      threw = true;
    }
    if (n > 1) REQUIRE(all_ranks(threw));
  }
  // Whatever failed, the context still works for everyone.
  const tessera::FieldView replica = ctx.assemble(local.view(), placement(box, kGlobal));
  const std::vector<unsigned char> expect = global_bytes(kGlobal, DType::Float32, value);
  REQUIRE(all_ranks(holds(replica, expect)));
}

TEST_CASE("adaptive sampling over 1-4 ranks, with tiles that cut its blocks, equals one core render",
          "[mpi][render][determinism][adaptive]") {
  const auto value = blobs(kGlobal);
  const std::vector<unsigned char> global = global_bytes(kGlobal, DType::Float32, value);
  const tessera::FieldView whole =
      tessera::FieldView::contiguous(global.data(), DType::Float32, kGlobal[0], kGlobal[1], kGlobal[2]);
  tessera::SceneDesc scene = scene_for(tessera::Scattering::Single, 1);
  scene.image = {61, 45, 48, 0.1};
  scene.options.tile = 3;  // tiles grabbed by different ranks share the 8x8 adaptive blocks
  const tessera::PreparedScene ref_prepared = tessera::prepare(whole, scene);
  tessera::Film ref(scene.image.width, scene.image.height);
  tessera::RenderStats ref_stats;
  tessera::render(ref_prepared, ref, ref_stats);
  std::uint64_t lo = ~0ull, hi = 0;
  for (const tessera::PixelSums& p : ref.pixels()) lo = std::min(lo, p.n), hi = std::max(hi, p.n);
  REQUIRE(lo < hi);  // the counts do adapt
  for (int n : sizes_up_to_world()) {
    FirstRanks sub(n);
    bool ok = true;
    if (sub.member()) {
      MpiParallelContext ctx(sub.comm(), 0);
      const Box box = block_of(kGlobal, procs_for(n), ctx.rank());
      const LocalArray local(box, DType::Float32, Layout::MirroredJ, value);
      const tessera::FieldView replica = ctx.assemble(local.view(), placement(box, kGlobal));
      const tessera::PreparedScene prepared = tessera::prepare(replica, scene);
      tessera::Film film(scene.image.width, scene.image.height);
      tessera::RenderStats stats;
      ctx.render(prepared, film, stats);
      if (ctx.rank() == 0) ok = same_pixels(film, ref) && stats.samples == ref_stats.samples;
    }
    INFO("ranks " << n);
    REQUIRE(all_ranks(ok));
  }
}
