// `field: {magnitude: [u, v, w]}`: a vector's magnitude rendered from the simulation's three
// component arrays. On one rank holding the grid whole it is read in place (no copy); with
// several domains (and on several ranks, tests/mpi) each block's magnitudes are staged. Either
// way the image is bit-identical to rendering a float64 array that holds magnitude() of the
// components. Components that do not fit together are refused by name.
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/magnitude_field.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

constexpr std::int64_t NX = 14, NY = 12, NZ = 10;

/// u, v (float32, separate) and w (the middle of three interleaved doubles), their magnitude as
/// float64, all on one NX x NY x NZ grid (i fastest).
struct Vectors {
  std::vector<float> u, v;
  std::vector<double> w3, mag;
  Vectors() {
    const auto n = static_cast<std::size_t>(NX * NY * NZ);
    u.resize(n), v.resize(n), w3.resize(3 * n), mag.resize(n);
    for (std::int64_t k = 0; k < NZ; ++k)
      for (std::int64_t j = 0; j < NY; ++j)
        for (std::int64_t i = 0; i < NX; ++i) {
          const auto e = static_cast<std::size_t>((k * NY + j) * NX + i);
          const double x = i / double(NX - 1) - 0.5, y = j / double(NY - 1) - 0.5, z = k / double(NZ - 1) - 0.5;
          u[e] = static_cast<float>(-y * 2.0 + 0.3 * z);
          v[e] = static_cast<float>(x * 2.0);
          w3[3 * e + 1] = std::exp(-8.0 * (x * x + y * y)) * (z + 0.5);
          w3[3 * e] = w3[3 * e + 2] = std::nan("");  // the other components of the interleaved array
          mag[e] = tessera::magnitude(u[e], v[e], w3[3 * e + 1]);
        }
  }
};

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

tessera_field field_of(const char* name, const void* data, tessera_dtype dt, std::int64_t elem_bytes) {
  tessera_field f{};
  f.name = name;
  f.data = data;
  f.dtype = dt;
  const std::int64_t d[3] = {NX, NY, NZ};
  std::int64_t s = elem_bytes;
  for (int a = 0; a < 3; ++a) {
    f.dims[a] = d[a];
    f.byte_strides[a] = s;
    s *= d[a];
  }
  return f;
}

tessera_grid grid() {
  tessera_grid g{};
  const std::int64_t d[3] = {NX, NY, NZ};
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = -0.5;
    g.spacing[a] = 1.0 / double(d[a] - 1);
    g.global_dims[a] = d[a];
  }
  return g;
}

std::string both_renders(const std::string& vec) {
  const std::string tf = "    transfer_function: {range: auto, density_scale: 30, opacity: [[0, 0], [1, 1]], "
                         "diffuse: viridis}\n";
  return render_yaml("vec", "", tf, vec, 24, 2) + render_yaml("copy", "", tf, "mag", 24, 2);
}

}  // namespace

TEST_CASE("vector magnitude: read in place on one rank, bit-identical to a float64 copy of it", "[insitu][magnitude]") {
  TempDir dir;
  const Vectors vec;
  std::vector<tessera_field> fields = {
      field_of("u", vec.u.data(), TESSERA_FLOAT32, 4), field_of("v", vec.v.data(), TESSERA_FLOAT32, 4),
      field_of("w", vec.w3.data() + 1, TESSERA_FLOAT64, 24), field_of("mag", vec.mag.data(), TESSERA_FLOAT64, 8)};
  const tessera_grid g = grid();
  Adapter ad;
  ad.set_quiet(true);
  REQUIRE(ad.open(dir.write("v.yaml", config_yaml(dir.file("out"), both_renders("{magnitude: [u, v, w]}")))) ==
          TESSERA_OK);
  const tessera_status st = ad.execute(1, 0.0, g, fields);
  INFO(ad.last_error());
  REQUIRE(st == TESSERA_OK);
  REQUIRE(ad.last_image("vec"));
  REQUIRE(ad.last_image("copy"));
  CHECK(same_pixels(*ad.last_image("vec"), *ad.last_image("copy")));
  CHECK(mean_luminance(*ad.last_image("vec")) > 0.0);
  // The effective config writes the magnitude back as it was given
  const std::string effective = read_text(dir.file("out") + "/tessera_effective_config.yaml");
  CHECK_THAT(effective, Contains("magnitude: [u, v, w]"));
}

TEST_CASE("vector magnitude: several domains are staged and render as the whole grid's copy",
          "[insitu][magnitude][domains]") {
  TempDir dir;
  const Dims g{12, 10, 8};
  // Three components of the same cut (each the blob field), their fields renamed
  HeldDomains hu(g, tessera_test::seven_cuts(g)), hv(g, tessera_test::seven_cuts(g)),
      hw(g, tessera_test::seven_cuts(g));
  std::vector<std::vector<tessera_field>> per(hu.size());
  std::vector<tessera_domain> domains;
  for (std::size_t n = 0; n < hu.size(); ++n) {
    tessera_field a = hu.field(n), b = hv.field(n), c = hw.field(n);
    a.name = "u", b.name = "v", c.name = "w";
    per[n] = {a, b, c};
    tessera_domain d = hu.domain(n);
    d.fields = per[n].data();
    d.nfields = 3;
    domains.push_back(d);
  }
  // The reference: one domain holding magnitude() of the three, whole
  std::vector<double> mag(static_cast<std::size_t>(g[0] * g[1] * g[2]));
  for (std::int64_t k = 0; k < g[2]; ++k)
    for (std::int64_t j = 0; j < g[1]; ++j)
      for (std::int64_t i = 0; i < g[0]; ++i) {
        const double x = tessera_test::global_value(g, i, j, k);
        mag[static_cast<std::size_t>((k * g[1] + j) * g[0] + i)] = tessera::magnitude(x, x, x);
      }
  tessera_field m{};
  m.name = "mag";
  m.data = mag.data();
  m.dtype = TESSERA_FLOAT64;
  for (int a = 0; a < 3; ++a) m.dims[a] = g[a];
  m.byte_strides[0] = 8, m.byte_strides[1] = 8 * g[0], m.byte_strides[2] = 8 * g[0] * g[1];
  tessera_domain whole{};
  whole.fields = &m;
  whole.nfields = 1;
  const tessera_mesh mesh = tessera_test::unit_mesh(g, TESSERA_VERTEX);
  const auto render = [&](const std::string& name, const std::string& field, const std::vector<tessera_domain>& d) {
    Adapter ad;
    ad.set_quiet(true);
    REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), render_yaml("r", "", "", field)))) ==
            TESSERA_OK);
    const tessera_status st = ad.execute_domains(1, 0.0, mesh, d);
    INFO(ad.last_error());
    REQUIRE(st == TESSERA_OK);
    return *ad.last_image("r");
  };
  const tessera::Image staged = render("staged", "{magnitude: [u, v, w]}", domains);
  const tessera::Image copy = render("copy", "mag", {whole});
  CHECK(same_pixels(staged, copy));
}

TEST_CASE("vector magnitude: components that do not fit together, or are missing, are refused by name",
          "[insitu][magnitude][errors]") {
  TempDir dir;
  const Vectors vec;
  const tessera_grid g = grid();
  const auto run = [&](const std::string& name, std::vector<tessera_field> fields, const std::string& field) {
    Adapter ad;
    ad.set_quiet(true);
    REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), render_yaml("r", "", "", field)))) ==
            TESSERA_OK);
    const tessera_status st = ad.execute(1, 0.0, g, fields);
    return std::pair{st, ad.last_error()};
  };
  std::vector<tessera_field> fields = {field_of("u", vec.u.data(), TESSERA_FLOAT32, 4),
                                       field_of("v", vec.v.data(), TESSERA_FLOAT32, 4)};
  auto [st, err] = run("missing", fields, "{magnitude: [u, v, w]}");
  CHECK(st == TESSERA_ERROR_DATA);
  CHECK_THAT(err, Contains("'w'"));
  // A component whose array is smaller than the grid
  fields.push_back(field_of("w", vec.w3.data() + 1, TESSERA_FLOAT64, 24));
  fields[2].dims[0] = NX - 1;
  std::tie(st, err) = run("short", fields, "{magnitude: [u, v, w]}");
  CHECK(st == TESSERA_ERROR_DATA);
  CHECK_THAT(err, Contains("field 'w'"));
}
