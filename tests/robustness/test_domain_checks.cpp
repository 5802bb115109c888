// tessera_execute_domains' checks on one rank: bad meshes and domains (overlaps, gaps,
// domains outside the mesh, non-finite or non-increasing coordinates, ghosts larger than the
// array, NULL or mismatched field lists, levels out of range, NULL arguments, ndomains out of
// range) fail at once with TESSERA_ERROR_DATA naming the domain, field and axis, and write
// nothing. (Ranks that disagree: tests/mpi/test_domains_mpi.cpp.)
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using tessera_test::Dims;
using tessera_test::HeldDomains;
using Catch::Matchers::Contains;

namespace {

const Dims kG{23, 19, 17};

std::string domains_config(const TempDir& dir, const std::string& out, const std::string& scattering) {
  return dir.write("cfg_" + out + ".yaml",
                   config_yaml(dir.file(out), render_yaml("view", "{every: 1}",
                                                          "    integrator: {scattering: " + scattering +
                                                              ", max_bounces: 4, tile: 8, seed: 3}\n",
                                                          "density", 28, 3)));
}

struct Outcome {
  tessera_status status;
  std::string error;
};
Outcome run_domains(const TempDir& dir, const std::string& out, const tessera_mesh& mesh,
                    std::span<const tessera_domain> domains) {
  Adapter ad;
  REQUIRE(ad.open(domains_config(dir, out, "single")) == TESSERA_OK);
  ad.set_quiet(true);
  Outcome o;
  o.status = ad.execute_domains(2, 0.0, mesh, domains);
  o.error = ad.last_error();
  return o;
}

}  // namespace

TEST_CASE("domains: bad meshes and domains fail with TESSERA_ERROR_DATA naming what and where, writing nothing",
          "[insitu][domains][errors]") {
  TempDir dir;
  std::vector<double> bad_coords(kG[1], 0.0);
  for (std::size_t q = 0; q < bad_coords.size(); ++q) bad_coords[q] = 0.1 * static_cast<double>(q);
  struct Case {
    const char* name;
    std::function<void(tessera_mesh&, std::vector<tessera_domain>&, HeldDomains&)> edit;
    std::vector<std::string> words;
  };
  static tessera_field other_name, other_dtype, two[2];
  const std::vector<Case> cases = {
      {"overlap",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[3].offset[1] -= 1; },
       {"domain 3", "overlap", "domain 2"}},
      {"gap", [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d.pop_back(); }, {"cover", "of the"}},
      {"outside the mesh",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[6].offset[2] += 1; },
       {"domain 6", "field 'density'", "along k", "leave the mesh"}},
      {"negative offset",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[0].offset[0] = -1; },
       {"domain 0", "along i", "leave the mesh"}},
      {"NaN origin",
       [](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) { m.origin[1] = NAN; },
       {"mesh: origin[1] (j)", "not finite"}},
      {"infinite spacing",
       [](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) { m.spacing[2] = INFINITY; },
       {"mesh: spacing[2] (k)"}},
      {"non-increasing coordinates",
       [&](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) {
         bad_coords[5] = bad_coords[4];
         m.coords[1] = bad_coords.data();
       },
       {"coords[1] (j)[5]", "strictly increasing"}},
      {"NaN coordinate",
       [&](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) {
         bad_coords[7] = NAN;
         m.coords[1] = bad_coords.data();
       },
       {"coords[1] (j)[", "not finite"}},
      {"ghosts larger than the array",
       [](tessera_mesh&, std::vector<tessera_domain>&, HeldDomains& h) { h.field(4).ghosts_hi[2] = 1000; },
       {"domain 4", "field 'density'", "ghost layers along k"}},
      {"NULL fields",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[2].fields = nullptr; },
       {"domain 2", "field list is invalid", "NULL"}},
      {"negative nfields",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[1].nfields = -1; },
       {"domain 1", "field list is invalid"}},
      {"a field of another name",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains& h) {
         other_name = h.field(5);
         other_name.name = "temperature";
         d[5].fields = &other_name;
       },
       {"domain 5", "'density'", "missing"}},
      {"a field of another dtype",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains& h) {
         other_dtype = h.field(2);
         other_dtype.dtype = TESSERA_FLOAT64;
         d[2].fields = &other_dtype;
       },
       {"domain 2", "field 'density'", "dtype", "float64", "float32"}},
      {"a field published twice",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains& h) {
         two[0] = two[1] = h.field(0);
         d[0].fields = two;
         d[0].nfields = 2;
       },
       {"domain 0", "published twice"}},
      {"AMR levels without their ratios",
       [](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) { m.nlevels = 2; },
       {"refinement is NULL", "nlevels = 2"}},
      {"a domain at level 1 of a single-level mesh",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d[3].level = 1; },
       {"domain 3", "level 1", "outside [0, 1)"}},
      {"bad association",
       [](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) { m.association = tessera_association(7); },
       {"association 7"}},
      {"global_dims 0",
       [](tessera_mesh& m, std::vector<tessera_domain>&, HeldDomains&) { m.global_dims[0] = 0; },
       {"global_dims[0] (i)"}},
      {"no domains",
       [](tessera_mesh&, std::vector<tessera_domain>& d, HeldDomains&) { d.clear(); },
       {"no rank passed a domain"}},
  };
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.name) {
      tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
      HeldDomains held(kG, tessera_test::seven_cuts(kG));
      std::vector<tessera_domain> d = held.of_rank(0, 1);
      c.edit(mesh, d, held);
      const std::string out = std::string("bad_") + std::to_string(&c - cases.data());
      const Outcome o = run_domains(dir, out, mesh, d);
      INFO(o.error);
      CHECK(o.status == TESSERA_ERROR_DATA);
      for (const std::string& w : c.words) CHECK_THAT(o.error, Contains(w));
      CHECK(!std::filesystem::exists(dir.file(out) + "/view_0002.exr"));
    }
  }
}

TEST_CASE("domains: the C API's argument checks (NULL mesh, NULL domains, ndomains out of range)",
          "[insitu][domains][errors]") {
  TempDir dir;
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(domains_config(dir, "c_api", "single").c_str(), -1, &a) == TESSERA_OK);
  const tessera_mesh mesh = tessera_test::unit_mesh(kG, TESSERA_VERTEX);
  const HeldDomains held(kG, tessera_test::seven_cuts(kG));
  const std::vector<tessera_domain> d = held.of_rank(0, 1);
  CHECK(tessera_execute_domains(a, 1, 0.0, nullptr, d.data(), 7) == TESSERA_ERROR_DATA);
  CHECK_THAT(tessera_last_error(a), Contains("mesh descriptor is NULL"));
  CHECK(tessera_execute_domains(a, 1, 0.0, &mesh, nullptr, 7) == TESSERA_ERROR_DATA);
  CHECK_THAT(tessera_last_error(a), Contains("domains is NULL with ndomains = 7"));
  CHECK(tessera_execute_domains(a, 1, 0.0, &mesh, d.data(), -1) == TESSERA_ERROR_DATA);
  CHECK_THAT(tessera_last_error(a), Contains("ndomains = -1"));
  CHECK(tessera_execute_domains(a, 1, 0.0, &mesh, d.data(), TESSERA_MAX_DOMAINS + 1) == TESSERA_ERROR_DATA);
  CHECK_THAT(tessera_last_error(a), Contains("TESSERA_MAX_DOMAINS"));
  CHECK(tessera_execute_domains(a, 1, 0.0, &mesh, d.data(), 7) == TESSERA_OK);
  CHECK(tessera_execute_domains_final(a, 2, 0.0, &mesh, d.data(), 7) == TESSERA_OK);
  CHECK(tessera_close(a) == TESSERA_OK);
}
