// FieldPlan (insitu/src/field_plan.h): the `distribution` rule, the brick size and the cache's
// bound, decided before anything is allocated.
#include "data/field_plan.h"

#include <tessera/brick_cache.h>
#include <tessera/config/config.h>
#include <tessera/memory_estimate.h>

#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <vector>

using namespace tessera;
using namespace tessera::insitu;

namespace {

config::Config config_for(const std::string& distribution, int memory_limit_mb) {
  return config::parse_config("tessera: {distribution: " + distribution +
                                  ", memory_limit_mb: " + std::to_string(memory_limit_mb) +
                                  "}\nrenders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
                                  "    image: {width: 64, height: 64, spp: 1}\n"
                                  "    transfer_function: {opacity: [[0, 1]]}\n",
                              "plan.yaml", "");
}

/// A float32 binding of a global grid of n^3 vertices (this rank's block: one plane).
FieldBinding binding_for(std::int64_t n) {
  FieldBinding b;
  b.local.dtype = DType::Float32;
  for (int a = 0; a < 3; ++a) {
    b.placement.global_dims[a] = n;
    b.placement.offset[a] = 0;
    b.local.dims[a] = a == 2 ? 1 : n;
  }
  return b;
}

}  // namespace

TEST_CASE("distribution: auto is replicated while a rank's replica share fits half the limit",
          "[insitu][distribution]") {
  const config::Config cfg = config_for("auto", 1024);
  const auto& spec = cfg.renders[0];
  // 256^3 float32 = 64 MiB; one rank per node: 64 MiB <= 512 MiB -> replicated
  CHECK_FALSE(plan_field(cfg, spec, binding_for(256), 4, 1, true).distributed);
  // 640^3 float32 = 1000 MiB > 512 MiB -> distributed; shared by 4 ranks on the node: 250 MiB -> replicated
  CHECK(plan_field(cfg, spec, binding_for(640), 4, 1, true).distributed);
  CHECK_FALSE(plan_field(cfg, spec, binding_for(640), 4, 4, true).distributed);
  // One rank is always replicated (its block is the whole field)
  CHECK_FALSE(plan_field(cfg, spec, binding_for(640), 1, 1, true).distributed);
}

TEST_CASE("plan: a render on the GPU counts its calls' host copies of the pixels", "[insitu][distribution]") {
  const config::Config cfg = config_for("auto", 1024);
  const FieldPlan cpu = plan_field(cfg, cfg.renders[0], binding_for(64), 1, 1, true);
  const FieldPlan gpu = plan_field(cfg, cfg.renders[0], binding_for(64), 1, 1, true, nullptr, true);
  const std::uint64_t pixels = static_cast<std::uint64_t>(cfg.renders[0].image.width) * cfg.renders[0].image.height;
  CHECK(gpu.base.total() - cpu.base.total() == pixels * tessera::kGpuHostBytesPerPixel);
  CHECK_THAT(gpu.base.describe(), Catch::Contains("GPU call's host copies"));
}

TEST_CASE("distribution: replicated over the limit fails naming the replica, distributed fits",
          "[insitu][distribution]") {
  const config::Config rep = config_for("replicated", 512), dist = config_for("distributed", 512);
  const FieldBinding b = binding_for(640);  // 1000 MiB
  try {
    plan_field(rep, rep.renders[0], b, 4, 1, true);
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Contains("field replica") && Catch::Contains("memory_limit_mb = 512 MiB"));
  }
  FieldPlan plan = plan_field(dist, dist.renders[0], b, 4, 1, true);
  REQUIRE(plan.distributed);
  plan_distributed(plan, b);
  CHECK(plan.shift == 5);  // 640 / 8 = 80 -> bricks of 32
  const BrickGrid g = BrickGrid::make(b.placement.global_dims, DType::Float32, plan.shift);
  // The cache fits the limit with the rest of the render, and stays under 40% of the field
  CHECK(plan.capacity >= 1);
  CHECK(BrickCache::bytes_for(g, plan.capacity) + plan.base.total() <= (std::uint64_t{512} << 20));
  CHECK(static_cast<double>(plan.capacity * g.slot_bytes()) <= kCacheFieldFraction * 1000.0 * (1 << 20));
}

TEST_CASE("a distributed render on the GPU counts the host's bookkeeping of the device's bricks",
          "[insitu][distribution]") {
  // A limit that bounds the cache: the GPU's plan has the per-brick bookkeeping and one slot's
  // fill buffer (beside its pixel copies) fewer bytes for the cache
  const config::Config dist = config_for("distributed", 300);
  const FieldBinding b = binding_for(640);
  FieldPlan cpu = plan_field(dist, dist.renders[0], b, 4, 1, true);
  FieldPlan gpu = plan_field(dist, dist.renders[0], b, 4, 1, true, nullptr, true);
  plan_distributed(cpu, b);
  plan_distributed(gpu, b);
  REQUIRE(gpu.shift == cpu.shift);
  const BrickGrid g = BrickGrid::make(b.placement.global_dims, DType::Float32, gpu.shift);
  const std::uint64_t limit = std::uint64_t{300} << 20;
  const std::uint64_t used = gpu.base.total() + BrickCache::bytes_for(g, 0) +
                             kGpuHostBytesPerBrick * static_cast<std::uint64_t>(g.brick_count()) + g.slot_bytes();
  CHECK(gpu.capacity == (limit - used) / g.slot_bytes());
  CHECK(cpu.capacity == (limit - cpu.base.total() - BrickCache::bytes_for(g, 0)) / g.slot_bytes());
  CHECK(gpu.capacity < cpu.capacity);
}

TEST_CASE("a distributed render whose limit leaves no room for one brick fails before allocating",
          "[insitu][distribution]") {
  const config::Config dist = config_for("distributed", 1);
  FieldPlan plan = plan_field(dist, dist.renders[0], binding_for(4096), 4, 1, true);
  CHECK_THROWS_WITH(plan_distributed(plan, binding_for(4096)), Catch::Contains("brick"));
}

TEST_CASE("bricks are 8 to 32 vertices, about an eighth of the longest axis", "[insitu][distribution]") {
  const std::int64_t small[3] = {23, 19, 17}, mid[3] = {128, 64, 64}, big[3] = {4096, 4096, 4096};
  CHECK(brick_shift(small) == 3);
  CHECK(brick_shift(mid) == 4);
  CHECK(brick_shift(big) == 5);
}

TEST_CASE("tessera.brick_cache caps the cache at its share of the field and refuses absurd values",
          "[insitu][distribution]") {
  const auto with_cache = [](const std::string& value) {
    return config::parse_config("tessera: {distribution: distributed, memory_limit_mb: 4096, brick_cache: " + value +
                                    "}\nrenders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
                                    "    image: {width: 64, height: 64, spp: 1}\n"
                                    "    transfer_function: {opacity: [[0, 1]]}\n",
                                "plan.yaml", "");
  };
  const FieldBinding b = binding_for(256);  // 64 MiB, bricks of 32^3 (128 KiB)
  const BrickGrid g = BrickGrid::make(b.placement.global_dims, DType::Float32, brick_shift(b.placement.global_dims));
  const auto capacity = [&](const config::Config& cfg) {
    FieldPlan plan = plan_field(cfg, cfg.renders[0], b, 4, 1, true);
    plan_distributed(plan, b);
    return plan.capacity;
  };
  REQUIRE(g.brick_count() == 512);
  CHECK(config_for("distributed", 4096).global.brick_cache == kCacheFieldFraction);
  CHECK(capacity(config_for("distributed", 4096)) == static_cast<std::size_t>(0.4 * 512));
  CHECK(capacity(with_cache("1")) == 512);  // every brick fits
  CHECK(capacity(with_cache("0.25")) == 128);
  CHECK(capacity(with_cache("1e-300")) == 1);  // never less than one brick
  // A cache that may keep every brick takes the coarsest cut (32^3) when the limit allows:
  // nothing is ever evicted, fewer messages. Otherwise the cut stays at an eighth of the axis.
  const auto plan_for = [&](const config::Config& cfg, std::int64_t n, int shift) {
    FieldPlan plan = plan_field(cfg, cfg.renders[0], binding_for(n), 4, 1, true);
    plan_distributed(plan, binding_for(n), shift);
    return plan;
  };
  CHECK(plan_for(config_for("distributed", 4096), 96, 0).shift == 3);
  CHECK(plan_for(with_cache("0.9"), 96, 0).shift == 3);
  CHECK(plan_for(with_cache("1"), 96, 0).shift == 5);
  CHECK(plan_for(with_cache("1"), 96, 0).capacity == 27);
  CHECK(plan_for(with_cache("1"), 100, 0).shift == 5);  // padded far faces count: 4^3 bricks
  CHECK(plan_for(with_cache("1"), 100, 0).capacity == 64);
  CHECK(plan_for(with_cache("1"), 100, 3).shift == 3);  // imposed by the ranks' agreement
  CHECK(plan_for(with_cache("1"), 100, 3).capacity == 13 * 13 * 13);
  for (const char* bad : {"0", "-0.5", "1.5", ".nan", ".inf", "lots", "[0.5]"})
    CHECK_THROWS_WITH(with_cache(bad), Catch::Contains("brick_cache"));
}

TEST_CASE("a distributed cache too small for the bricks the paths cross is warned about", "[insitu][distribution]") {
  const std::int64_t dims[3] = {96, 96, 96};
  const BrickGrid g8 = BrickGrid::make(dims, DType::Float32, 3);   // 12^3 bricks, 36 along x + y + z
  const BrickGrid g32 = BrickGrid::make(dims, DType::Float32, 5);  // 3^3 bricks, 9 along x + y + z
  // The default 40% of 1728 bricks (691) against 4 x 1 thread x 36: no warning
  CHECK(small_cache_warning(g8, 691, 1, 0.4).empty());
  CHECK(small_cache_warning(g8, 144, 1, 0.4).empty());  // exactly 4 x 36
  // One brick, or too few for the threads: a warning naming the figures and the remedies
  const std::string one = small_cache_warning(g8, 1, 1, 1e-300);
  CHECK_THAT(one, Catch::Contains("holds 1 of the field's 1728 bricks (8^3 vertices)"));
  CHECK_THAT(one, Catch::Contains("4 x 1 thread(s) x 36 bricks along x + y + z"));
  CHECK_THAT(one, Catch::Contains("tessera.brick_cache (now 1e-300)"));
  CHECK_THAT(one, Catch::Contains("distribution: replicated"));
  CHECK_FALSE(small_cache_warning(g8, 143, 1, 0.4).empty());
  CHECK_FALSE(small_cache_warning(g8, 691, 8, 0.4).empty());  // 4 x 8 x 36 = 1152 slots wanted
  // A cache of every brick never warns, however many threads
  CHECK(small_cache_warning(g32, 27, 64, 1.0).empty());
  CHECK_FALSE(small_cache_warning(g32, 10, 1, 0.4).empty());  // 32^3 bricks at 40%: 14x slower measured

  // Through the plan: a one-brick cache warns, a cache of every brick does not
  const auto plan_for = [](const std::string& cache) {
    const config::Config cfg = config::parse_config(
        "tessera: {distribution: distributed, memory_limit_mb: 4096, threads: 1, brick_cache: " + cache +
            "}\nrenders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
            "    image: {width: 64, height: 64, spp: 1}\n"
            "    transfer_function: {opacity: [[0, 1]]}\n",
        "plan.yaml", "");
    FieldPlan plan = plan_field(cfg, cfg.renders[0], binding_for(96), 4, 1, true);
    plan_distributed(plan, binding_for(96));
    return plan;
  };
  CHECK(plan_for("1e-300").capacity == 1);
  CHECK_THAT(plan_for("1e-300").cache_warning, Catch::Contains("holds 1 of the field's"));
  CHECK(plan_for("1").cache_warning.empty());
}

TEST_CASE("one rank: one domain covering the mesh is read in place, several domains cost a replica",
          "[insitu][distribution][domains]") {
  const config::Config cfg = config_for("auto", 1024);
  const auto& spec = cfg.renders[0];
  FieldBinding whole = binding_for(256);  // 64 MiB
  whole.domains = true;
  whole.local.dims[2] = 256;
  whole.blocks.push_back(FieldBlock{whole.local, {0, 0, 0}, 0});
  CHECK(plan_field(cfg, spec, whole, 1, 1, true).replica_share == 0);
  FieldBinding two = whole;
  two.blocks[0].view.dims[2] = 100;
  two.blocks.push_back(FieldBlock{whole.local, {0, 0, 100}, 1});
  two.blocks[1].view.dims[2] = 156;
  CHECK(plan_field(cfg, spec, two, 1, 1, true).replica_share == 64u << 20);
  // ... and the replica counts against the limit
  const config::Config small = config_for("auto", 48);
  try {
    plan_field(small, small.renders[0], two, 1, 1, true);
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Catch::Contains("the domains' copy"));
  }
}

TEST_CASE("the plan's estimate counts the axis tables of a rectilinear mesh, and only of its rectilinear axes",
          "[insitu][distribution][rectilinear]") {
  const config::Config cfg = config_for("replicated", 1024);
  const auto& spec = cfg.renders[0];
  const auto axis_part = [](const MemoryEstimate& e) {
    for (const MemoryEstimate::Part& p : e.parts)
      if (p.name == "axis tables") return p.bytes;
    return std::uint64_t{0};
  };
  FieldBinding b = binding_for(200);
  CHECK(axis_part(plan_field(cfg, spec, b, 1, 1, true).base) == 0);  // uniform: no part
  const std::vector<double> y(200, 0.0);  // never read: only which axes are rectilinear counts
  b.geometry.coords[1] = y.data();
  const std::uint64_t one = axis_part(plan_field(cfg, spec, b, 1, 1, true).base);
  // At most 4 (n - 1) + 65 bin entries and a wall per macrocell, 8 bytes each: more than the
  // bins' 4 (n - 1) entries alone
  CHECK(one >= 8 * 4 * 199);
  CHECK(one <= 8 * (4 * 199 + 65 + 200 + 1));
  b.geometry.coords[0] = b.geometry.coords[2] = y.data();
  CHECK(axis_part(plan_field(cfg, spec, b, 1, 1, true).base) == 3 * one);
  CHECK_THAT(plan_field(cfg, spec, b, 1, 1, true).base.describe(), Catch::Contains("axis tables"));
}
