// Refinement levels on one rank (tessera_execute_domains): bad hierarchies fail at once with
// TESSERA_ERROR_DATA naming the rank, domain, level and axis, and write nothing: a ratio
// other than 2 or 4, refinement NULL, nlevels out of [1, 8], a level out of [0, nlevels), a
// patch outside its level, a finer patch outside its coarser level, overlap within a level,
// a gap in level 0, rectilinear axes with levels ("not yet"); a refinement pattern whose
// tables would exceed tessera.memory_limit_mb fails with the limit's message (before any
// table is built). Ranks that disagree: tests/mpi/test_amr_mpi.cpp.
#include "amr_patches.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/amr.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using tessera_test::AmrBoxSpec;
using tessera_test::AmrMeshSpec;
using tessera_test::HeldPatches;
using Catch::Matchers::Contains;

namespace {

struct Outcome {
  tessera_status status;
  std::string error;
};

Outcome run(const TempDir& dir, const std::string& out, const tessera_mesh& mesh,
            const std::vector<tessera_domain>& domains, const std::string& global = "") {
  Adapter ad;
  const std::string cfg =
      dir.write("cfg_" + out + ".yaml",
                config_yaml(dir.file(out),
                            render_yaml("view", "{every: 1}",
                                        "    integrator: {scattering: single, tile: 8, seed: 3}\n", "density", 24, 2),
                            global));
  REQUIRE(ad.open(cfg) == TESSERA_OK);
  ad.set_quiet(true);
  Outcome o;
  o.status = ad.execute_domains(2, 0.0, mesh, domains);
  o.error = ad.last_error();
  return o;
}

double ramp(double x, double y, double z) { return 100.0 + 50.0 * x + 30.0 * y + 20.0 * z; }

/// Vertex data, ratios 2 and 2: level 0 of 13x11x9 vertices in two patches (domains 0, 1),
/// level 1 refining level-0 cells [2, 6) x [2, 7) x [2, 6) in two patches (domains 2, 3),
/// level 2 refining level-1 cells [5, 8) x [5, 9) x [5, 8) (domain 4).
const AmrMeshSpec kSpec{{13, 11, 9}, TESSERA_VERTEX, {2, 2}};
std::vector<AmrBoxSpec> good_boxes() {
  return {{0, {0, 0, 0}, {13, 11, 4}},
          {0, {0, 0, 4}, {13, 11, 5}},
          {1, {4, 4, 4}, {6, 11, 9}},
          {1, {10, 4, 4}, {3, 11, 9}},
          {2, {10, 10, 10}, {7, 9, 7}}};
}

}  // namespace

TEST_CASE("levels: bad hierarchies fail with TESSERA_ERROR_DATA naming what and where, writing nothing",
          "[insitu][amr][errors]") {
  TempDir dir;
  static const int ratio3[2] = {3, 2};
  static std::vector<double> coords;
  struct Case {
    const char* name;
    std::function<void(tessera_mesh&, std::vector<AmrBoxSpec>&, std::vector<int>&)> edit;
    std::vector<std::string> words;
  };
  // Edits of the mesh, of the boxes, or of the domains' levels (-1 = keep)
  const std::vector<Case> cases = {
      {"ratio 3",
       [](tessera_mesh& m, auto&, auto&) { m.refinement = ratio3; },
       {"refinement[0] = 3", "level 0 -> 1", "2 or 4"}},
      {"refinement NULL with nlevels 2",
       [](tessera_mesh& m, auto&, auto&) { m.refinement = nullptr; },
       {"refinement is NULL", "nlevels = 3"}},
      {"nlevels 0", [](tessera_mesh& m, auto&, auto&) { m.nlevels = 0; }, {"nlevels = 0", "[1, 8]"}},
      {"nlevels 9", [](tessera_mesh& m, auto&, auto&) { m.nlevels = 9; }, {"nlevels = 9", "[1, 8]"}},
      {"level -1",
       [](tessera_mesh&, auto&, std::vector<int>& lv) { lv[3] = -1; },
       {"domain 3", "level -1", "outside [0, 3)"}},
      {"level 3 of 3",
       [](tessera_mesh&, auto&, std::vector<int>& lv) { lv[2] = 3; },
       {"domain 2", "level 3", "outside [0, 3)"}},
      {"a patch outside its level",
       [](tessera_mesh&, std::vector<AmrBoxSpec>& b, auto&) { b[3].offset[1] = 20; },
       {"domain 3", "along j", "leave level 1's [0..21)"}},
      {"a finer patch outside its coarser level",
       [](tessera_mesh&, std::vector<AmrBoxSpec>& b, auto&) { b[4].offset[0] = 0; },
       {"rank 0 domain 4", "level 2"}},
      {"overlap within level 1",
       [](tessera_mesh&, std::vector<AmrBoxSpec>& b, auto&) { b[3].offset[0] = 9; },
       {"rank 0 domain 2", "rank 0 domain 3", "level 1"}},
      {"a gap in level 0", [](tessera_mesh&, std::vector<AmrBoxSpec>& b, auto&) { b[1].dims[0] = 12; }, {"level 0"}},
      {"rectilinear axes with levels",
       [](tessera_mesh& m, auto&, auto&) {
         coords.assign(11, 0.0);
         for (std::size_t q = 0; q < coords.size(); ++q) coords[q] = -0.5 + 0.1 * static_cast<double>(q);
         m.coords[1] = coords.data();
       },
       {"coords[1] (j)", "rectilinear", "not yet"}},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      tessera_mesh mesh = kSpec.mesh();
      std::vector<AmrBoxSpec> boxes = good_boxes();
      std::vector<int> levels(boxes.size(), -2);
      c.edit(mesh, boxes, levels);
      const HeldPatches held(kSpec, boxes, ramp);
      std::vector<tessera_domain> d = held.all();
      for (std::size_t n = 0; n < d.size(); ++n)
        if (levels[n] != -2) d[n].level = levels[n];
      const std::string out = std::string("bad_") + std::to_string(&c - cases.data());
      const Outcome o = run(dir, out, mesh, d);
      INFO(o.error);
      CHECK(o.status == TESSERA_ERROR_DATA);
      for (const std::string& w : c.words) CHECK_THAT(o.error, Contains(w));
      CHECK(!std::filesystem::exists(dir.file(out) + "/view_0002.exr"));
    }
  }
}

TEST_CASE("levels: the hierarchy the bad cases edit renders (each case fails for its own fault)",
          "[insitu][amr][errors]") {
  TempDir dir;
  const HeldPatches held(kSpec, good_boxes(), ramp);
  const Outcome ok = run(dir, "good", kSpec.mesh(), held.all());
  INFO(ok.error);
  CHECK(ok.status == TESSERA_OK);
  CHECK(std::filesystem::exists(dir.file("good") + "/view_0002.exr"));
}

TEST_CASE("levels: a refinement pattern whose level tables exceed tessera.memory_limit_mb fails with the limit",
          "[insitu][amr][limits]") {
  // Few values, tables larger than the limit (amr_patches.h DeepCorners)
  TempDir dir;
  const tessera_test::DeepCorners deep;
  const AmrMeshSpec& spec = deep.spec;
  const std::vector<AmrBoxSpec>& boxes = deep.boxes;
  const HeldPatches held(spec, boxes, ramp);
  // What the renderer would allocate for its tables, from the boxes alone: above the limit
  std::vector<tessera::AmrPatch> patches;
  for (const AmrBoxSpec& b : boxes) {
    tessera::AmrPatch p;
    p.level = b.level;
    for (int a = 0; a < 3; ++a) p.offset[a] = b.offset[a];
    p.view = tessera::FieldView::contiguous(&spec, tessera::DType::Float32, b.dims[0], b.dims[1], b.dims[2]);
    patches.push_back(p);
  }
  tessera::AmrField field;
  for (int a = 0; a < 3; ++a) field.dims[a] = spec.g[a];
  field.nlevels = 8;
  for (int l = 0; l < 7; ++l) field.ratio[l] = 4;
  field.patches = patches;
  constexpr int kLimitMiB = 4;
  const std::uint64_t tables = tessera::amr_table_bytes(field, tessera::Association::Cell, 4);
  INFO("level tables: " << tables << " bytes");
  REQUIRE(tables > (std::uint64_t{kLimitMiB} << 20));

  const Outcome o = run(dir, "deep", spec.mesh(), held.all(), "  memory_limit_mb: " + std::to_string(kLimitMiB) + "\n");
  INFO(o.error);
  CHECK(o.status == TESSERA_ERROR_RENDER);
  CHECK_THAT(o.error, Contains("refinement level tables"));
  CHECK_THAT(o.error, Contains("more than tessera.memory_limit_mb = 4 MiB"));
  CHECK(!std::filesystem::exists(dir.file("deep") + "/view_0002.exr"));
}

TEST_CASE("levels: nine thousand small patches are checked and rendered (checks cost per patch, not per pair)",
          "[insitu][amr][limits]") {
  // Level 0: 20^3 one-cell patches; level 1 (ratio 2) refining the middle 10^3 level-0 cells
  // in 1000 patches of 2^3 cells; the same image as one patch per level
  TempDir dir;
  const AmrMeshSpec spec{{20, 20, 20}, TESSERA_CELL, {2}};
  std::vector<AmrBoxSpec> small, whole{{0, {0, 0, 0}, {20, 20, 20}}, {1, {10, 10, 10}, {20, 20, 20}}};
  for (std::int64_t k = 0; k < 20; ++k)
    for (std::int64_t j = 0; j < 20; ++j)
      for (std::int64_t i = 0; i < 20; ++i) small.push_back({0, {i, j, k}, {1, 1, 1}});
  for (std::int64_t k = 0; k < 10; ++k)
    for (std::int64_t j = 0; j < 10; ++j)
      for (std::int64_t i = 0; i < 10; ++i) small.push_back({1, {10 + 2 * i, 10 + 2 * j, 10 + 2 * k}, {2, 2, 2}});
  const HeldPatches many(spec, small, tessera_test::blobs, 0);
  const HeldPatches two(spec, whole, tessera_test::blobs, 0);
  const auto image = [&](const std::string& out, const HeldPatches& held) {
    Adapter ad;
    REQUIRE(ad.open(dir.write("cfg_" + out + ".yaml",
                              config_yaml(dir.file(out), render_yaml("view", "{every: 1}", "", "density", 24, 2)))) ==
            TESSERA_OK);
    ad.set_quiet(true);
    const std::vector<tessera_domain> d = held.all();
    const auto t0 = std::chrono::steady_clock::now();
    const tessera_status st = ad.execute_domains(2, 0.0, spec.mesh(), d);
    INFO(ad.last_error());
    REQUIRE(st == TESSERA_OK);
    WARN(out << ": " << held.size() << " patches in "
             << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s");
    return *ad.last_image("view");
  };
  const tessera::Image a = image("many", many);
  const tessera::Image b = image("two", two);
  REQUIRE(a.rgba.size() == b.rgba.size());
  CHECK(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0);
}
