// tessera_execute_domains at its extremes: a million one-element domains on one rank are
// checked (the O(N log N) tiling check), copied into the replica and rendered in bounded
// time; a duplicate or a missing one among them fails fast, naming the domains; ndomains
// beyond TESSERA_MAX_DOMAINS is refused before anything is read.
#include "insitu_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <vector>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::int64_t kN = 100;  // 100^3 = 10^6 one-element domains

struct Tiny {
  std::vector<float> values;
  std::vector<tessera_field> fields;
  std::vector<tessera_domain> domains;
  tessera_mesh mesh{};
  Tiny() : values(static_cast<std::size_t>(kN * kN * kN)), fields(values.size()), domains(values.size()) {
    mesh.association = TESSERA_VERTEX;
    mesh.nlevels = 1;
    for (int a = 0; a < 3; ++a) {
      mesh.origin[a] = -0.5;
      mesh.spacing[a] = 1.0 / (kN - 1);
      mesh.global_dims[a] = kN;
    }
    for (std::int64_t k = 0; k < kN; ++k)
      for (std::int64_t j = 0; j < kN; ++j)
        for (std::int64_t i = 0; i < kN; ++i) {
          const auto n = static_cast<std::size_t>(i + kN * (j + kN * k));
          values[n] = static_cast<float>((i * 7 + j * 3 + k) % 50);
          tessera_field& f = fields[n];
          f.name = "density";
          f.data = &values[n];
          f.dtype = TESSERA_FLOAT32;
          f.dims[0] = f.dims[1] = f.dims[2] = 1;
          f.byte_strides[0] = 4;
          f.byte_strides[1] = 4 * kN;
          f.byte_strides[2] = 4 * kN * kN;
          tessera_domain& d = domains[n];
          d.offset[0] = i;
          d.offset[1] = j;
          d.offset[2] = k;
          d.fields = &f;
          d.nfields = 1;
        }
  }
};

struct Outcome {
  tessera_status status;
  std::string error;
  double seconds;
};

Outcome run(const Tiny& t, int ndomains, const tessera_domain* domains) {
  TempDir dir;
  const std::string cfg =
      dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("tiny", "{every: 1}", "", "density", 16, 1)));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  const auto t0 = Clock::now();
  const tessera_status s = tessera_execute_domains(a, 0, 0.0, &t.mesh, domains, ndomains);
  Outcome o{s, tessera_last_error(a), std::chrono::duration<double>(Clock::now() - t0).count()};
  CHECK(tessera_close(a) == TESSERA_OK);
  return o;
}

}  // namespace

TEST_CASE("domains: a million one-element domains on one rank render, or fail naming the domains, in bounded time",
          "[robustness][domains]") {
  const Tiny t;
  const int n = static_cast<int>(t.domains.size());
  SECTION("all of them: rendered") {
    const Outcome o = run(t, n, t.domains.data());
    INFO(o.error);
    CHECK(o.status == TESSERA_OK);
    CHECK(o.seconds < 60.0);
    WARN("10^6 domains: " << o.seconds << " s");
  }
  SECTION("one of them twice: an overlap naming both") {
    std::vector<tessera_domain> d = t.domains;
    d[n - 1] = d[12345];
    const Outcome o = run(t, n, d.data());
    CHECK(o.status == TESSERA_ERROR_DATA);
    CHECK_THAT(o.error, Contains("domain 12345") && Contains("overlap") && Contains("domain " + std::to_string(n - 1)));
    CHECK(o.seconds < 60.0);
  }
  SECTION("one of them missing: a gap") {
    const Outcome o = run(t, n - 1, t.domains.data() + 1);
    CHECK(o.status == TESSERA_ERROR_DATA);
    CHECK_THAT(o.error, Contains("cover 999999 of the 1000000"));
    CHECK(o.seconds < 60.0);
  }
  SECTION("more than TESSERA_MAX_DOMAINS: refused before any is read") {
    const Outcome o = run(t, TESSERA_MAX_DOMAINS + 1, t.domains.data());  // (the array is shorter: never read)
    CHECK(o.status == TESSERA_ERROR_DATA);
    CHECK_THAT(o.error, Contains("TESSERA_MAX_DOMAINS"));
    CHECK(o.seconds < 1.0);
  }
}
