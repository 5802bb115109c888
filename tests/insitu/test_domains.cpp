// tessera_execute_domains on one rank: the same global field cut into 1 or 7 uneven domains
// (own arrays, own layouts, NaN ghosts) renders bit-identically to tessera_execute of the
// whole field (bad input: tests/robustness/test_domain_checks.cpp), for vertex and cell data
// on uniform and stretched (rectilinear) axes.
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using tessera_test::Axes;
using tessera_test::CutBox;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{23, 19, 17};

std::string domains_config(const TempDir& dir, const std::string& out, const std::string& scattering) {
  return dir.write("cfg_" + out + ".yaml",
                   config_yaml(dir.file(out), render_yaml("view", "{every: 1}",
                                                          "    integrator: {scattering: " + scattering +
                                                              ", max_bounces: 4, tile: 8, seed: 3}\n",
                                                          "density", 28, 3)));
}

bool same_image(const tessera::Image& a, const tessera::Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

/// The image of the whole field through tessera_execute (one dense array, no ghosts).
tessera::Image reference_image(const TempDir& dir, const std::string& scattering) {
  std::vector<float> whole(static_cast<std::size_t>(kG[0] * kG[1] * kG[2]));
  for (std::int64_t k = 0; k < kG[2]; ++k)
    for (std::int64_t j = 0; j < kG[1]; ++j)
      for (std::int64_t i = 0; i < kG[0]; ++i)
        whole[static_cast<std::size_t>(i + kG[0] * (j + kG[1] * k))] = tessera_test::global_value(kG, i, j, k);
  tessera_field f{};
  f.name = "density";
  f.data = whole.data();
  f.dtype = TESSERA_FLOAT32;
  tessera_grid g{};
  for (int a = 0; a < 3; ++a) {
    f.dims[a] = kG[a];
    g.origin[a] = -0.5;
    g.spacing[a] = 1.0 / static_cast<double>(kG[a] - 1);
    g.global_dims[a] = kG[a];
  }
  f.byte_strides[0] = 4;
  f.byte_strides[1] = 4 * kG[0];
  f.byte_strides[2] = 4 * kG[0] * kG[1];
  Adapter ad;
  REQUIRE(ad.open(domains_config(dir, "ref_" + scattering, scattering)) == TESSERA_OK);
  ad.set_quiet(true);
  REQUIRE(ad.execute(2, 0.0, g, std::span<const tessera_field>(&f, 1)) == TESSERA_OK);
  return *ad.last_image("view");
}

/// What execute_domains returns for `domains` (and the adapter's message).
struct Outcome {
  tessera_status status;
  std::string error;
  std::optional<tessera::Image> image;
};
Outcome run_domains(const TempDir& dir, const std::string& out, const tessera_mesh& mesh,
                    std::span<const tessera_domain> domains, const std::string& scattering = "single") {
  Adapter ad;
  REQUIRE(ad.open(domains_config(dir, out, scattering)) == TESSERA_OK);
  ad.set_quiet(true);
  Outcome o;
  o.status = ad.execute_domains(2, 0.0, mesh, domains);
  o.error = ad.last_error();
  if (const tessera::Image* img = ad.last_image("view")) o.image = *img;
  return o;
}

}  // namespace

TEST_CASE("domains: 1 or 7 uneven domains on one rank render bit-identically to tessera_execute",
          "[insitu][domains][determinism]") {
  TempDir dir;
  std::map<std::string, tessera::Image> plain_ref;  // tessera_execute's image, per scattering
  for (const std::string scattering : {"single", "multiple"}) plain_ref[scattering] = reference_image(dir, scattering);
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL}) {
    for (const Axes axes : {Axes::Uniform, Axes::StretchedY, Axes::StretchedAll}) {
      for (const std::string scattering : {"single", "multiple"}) {
        INFO((assoc == TESSERA_CELL ? "cell" : "vertex")
             << " data, " << tessera_test::axes_name(axes) << ", " << scattering << " scattering");
        const tessera_test::TestMesh mesh(kG, assoc, axes);
        const HeldDomains one(kG, {CutBox{{0, 0, 0}, kG}});
        const HeldDomains seven(kG, tessera_test::seven_cuts(kG), 2);
        const std::string tag = std::to_string(assoc) + std::to_string(static_cast<int>(axes)) + scattering;
        const Outcome a = run_domains(dir, "one_" + tag, mesh.mesh(), one.of_rank(0, 1), scattering);
        REQUIRE(a.status == TESSERA_OK);
        // Uniform vertex data: tessera_execute of the whole field gives the same image; the
        // other meshes have only the one-domain call to compare with
        const bool plain = assoc == TESSERA_VERTEX && axes == Axes::Uniform;
        const tessera::Image ref = plain ? plain_ref.at(scattering) : *a.image;
        CHECK(same_image(ref, *a.image));
        const Outcome b = run_domains(dir, "seven_" + tag, mesh.mesh(), seven.of_rank(0, 1), scattering);
        REQUIRE(b.status == TESSERA_OK);
        CHECK(same_image(ref, *b.image));
        // Not the image of another mesh: the stretch and the association reach the renderer
        if (!plain) CHECK_FALSE(same_image(plain_ref.at(scattering), *b.image));
      }
    }
  }
}

TEST_CASE("domains: the first of 7 domains passed last, and in reverse order, change nothing",
          "[insitu][domains][determinism]") {
  TempDir dir;
  const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
  const HeldDomains seven(kG, tessera_test::seven_cuts(kG));
  std::vector<tessera_domain> d = seven.of_rank(0, 1);
  const Outcome a = run_domains(dir, "fwd", mesh, d);
  std::reverse(d.begin(), d.end());
  const Outcome b = run_domains(dir, "rev", mesh, d);
  REQUIRE(a.status == TESSERA_OK);
  REQUIRE(b.status == TESSERA_OK);
  CHECK(same_image(*a.image, *b.image));
}

TEST_CASE("domains: a call where nothing fires reads no descriptor", "[insitu][domains]") {
  TempDir dir;
  Adapter ad;
  REQUIRE(ad.open(dir.write("cfg.yaml", config_yaml(dir.file("o"), render_yaml("view", "{every: 5}")))) == TESSERA_OK);
  tessera_mesh bad{};  // invalid in every way: never looked at
  CHECK(ad.execute_domains(1, 0.0, bad, {}) == TESSERA_OK);
}

TEST_CASE("domains: field_unchanged keeps the summary of 7 domains, a moved domain drops it",
          "[insitu][domains][summary]") {
  TempDir dir;
  const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
  HeldDomains seven(kG, tessera_test::seven_cuts(kG));
  std::vector<tessera_domain> d = seven.of_rank(0, 1);
  Adapter ad;
  REQUIRE(ad.open(domains_config(dir, "unchanged", "single")) == TESSERA_OK);
  ad.set_quiet(true);
  REQUIRE(ad.execute_domains(1, 0.0, mesh, d) == TESSERA_OK);
  CHECK(ad.last_results()[0].field_passes >= 1);
  const tessera::Image first = *ad.last_image("view");
  REQUIRE(ad.field_unchanged("density") == TESSERA_OK);
  REQUIRE(ad.execute_domains(1, 0.0, mesh, d) == TESSERA_OK);
  CHECK(ad.last_results()[0].field_passes == 0);
  CHECK(same_image(first, *ad.last_image("view")));
  // The same promise with the domains listed in another order: another layout, read again
  REQUIRE(ad.field_unchanged("density") == TESSERA_OK);
  std::swap(d[0], d[1]);
  REQUIRE(ad.execute_domains(1, 0.0, mesh, d) == TESSERA_OK);
  CHECK(ad.last_results()[0].field_passes >= 1);
  CHECK(same_image(first, *ad.last_image("view")));
}

TEST_CASE("domains: cell data and rectilinear axes are passed through to the renderer and render",
          "[insitu][domains]") {
  TempDir dir;
  std::vector<double> y(static_cast<std::size_t>(kG[1]) + 1);
  for (std::size_t q = 0; q < y.size(); ++q) y[q] = -0.5 + 0.02 * static_cast<double>(q * q) / kG[1];
  for (const tessera_association assoc : {TESSERA_VERTEX, TESSERA_CELL})
    for (const bool rectilinear : {false, true}) {
      if (assoc == TESSERA_VERTEX && !rectilinear) continue;  // the case of every other test
      tessera_mesh mesh = tessera_test::unit_mesh(kG, assoc);
      if (rectilinear) mesh.coords[1] = y.data();  // kG[1] + 1 values: a cell mesh's boundaries
      const HeldDomains seven(kG, tessera_test::seven_cuts(kG));
      const Outcome o =
          run_domains(dir, "pass_" + std::to_string(assoc) + std::to_string(rectilinear), mesh, seven.of_rank(0, 1));
      INFO("association " << assoc << ", rectilinear " << rectilinear << ": " << o.error);
      CHECK(o.status == TESSERA_OK);
    }
}
