#pragma once
// Two renders or two runs of the estimator traced the same paths: every path counter equal
// (a Catch2 CHECK each). Shared by the core tests and the GPU tests.
#include <tessera/stats.h>

#include <catch2/catch.hpp>

namespace tessera_test {

inline void check_same_paths(const tessera::RenderStats& a, const tessera::RenderStats& b) {
  CHECK(a.samples == b.samples);
  CHECK(a.discarded_samples == b.discarded_samples);
  CHECK(a.free_flight_lookups == b.free_flight_lookups);
  CHECK(a.transmittance_lookups == b.transmittance_lookups);
  CHECK(a.gradient_lookups == b.gradient_lookups);
  CHECK(a.real_collisions == b.real_collisions);
  CHECK(a.null_collisions == b.null_collisions);
}

}  // namespace tessera_test
