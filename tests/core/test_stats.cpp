// RenderStats' counter table (kRenderCounters): every integer counter is a row with its own
// field and name, add_counters combines each by its rule, and the rules are the ones the
// docs state (events add up; the field's NaN count is the same wherever it is counted).
#include <tessera/stats.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <set>
#include <string>

using namespace tessera;

TEST_CASE("kRenderCounters: one row per counter, distinct fields and names", "[stats]") {
  std::set<std::string> names;
  RenderStats s;
  std::uint64_t v = 1;
  for (const RenderCounter& c : kRenderCounters) {
    CHECK(names.insert(c.name).second);
    s.*c.field = v++;
  }
  // Writing row i wrote a field no other row holds: reading back gives every value once
  v = 1;
  for (const RenderCounter& c : kRenderCounters) CHECK(s.*c.field == v++);
  // The rows address the fields the names say
  const auto field_named = [&](const char* name) -> std::uint64_t {
    for (const RenderCounter& c : kRenderCounters)
      if (std::strcmp(c.name, name) == 0) return s.*c.field;
    FAIL("no counter named " << name);
    return 0;
  };
  CHECK(field_named("samples") == s.samples);
  CHECK(field_named("free_flight_lookups") == s.free_flight_lookups);
  CHECK(field_named("transmittance_lookups") == s.transmittance_lookups);
  CHECK(field_named("gradient_lookups") == s.gradient_lookups);
  CHECK(field_named("real_collisions") == s.real_collisions);
  CHECK(field_named("null_collisions") == s.null_collisions);
  CHECK(field_named("discarded_samples") == s.discarded_samples);
  CHECK(field_named("stalled_paths") == s.stalled_paths);
  CHECK(field_named("nan_voxels_seen") == s.nan_voxels_seen);
  CHECK(field_named("tiles_total") == s.tiles_total);
  CHECK(field_named("tiles_skipped") == s.tiles_skipped);
}

TEST_CASE("add_counters sums events, keeps the larger NaN count, leaves time and threads", "[stats]") {
  RenderStats a, b;
  std::uint64_t v = 10;
  for (const RenderCounter& c : kRenderCounters) {
    a.*c.field = v;
    b.*c.field = 3 * v + 1;
    v += 10;
  }
  a.wall_seconds = 1.5;
  a.threads = 4;
  b.wall_seconds = 7.0;
  b.threads = 9;
  RenderStats sum = a;
  sum.add_counters(b);
  for (const RenderCounter& c : kRenderCounters) {
    INFO(c.name);
    const bool max = c.combine == RenderCounter::Combine::Max;
    CHECK(sum.*c.field == (max ? b.*c.field : a.*c.field + b.*c.field));
  }
  CHECK(sum.wall_seconds == 1.5);
  CHECK(sum.threads == 4);
  // Only the field's NaN count is kept-largest; everything else is an event count
  for (const RenderCounter& c : kRenderCounters)
    CHECK((c.combine == RenderCounter::Combine::Max) == (std::string(c.name) == "nan_voxels_seen"));
  // Adding zeros changes nothing
  RenderStats same = a;
  same.add_counters(RenderStats{});
  for (const RenderCounter& c : kRenderCounters) CHECK(same.*c.field == a.*c.field);
}
