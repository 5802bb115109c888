#include <tessera/stats.h>

#include <algorithm>
#include <cstdio>
#include <iterator>

namespace tessera {

// Every integer field is a row of kRenderCounters: 13 counters, then wall_seconds and threads
// (an int, padded to 8 bytes).
static_assert(sizeof(RenderStats) == sizeof(std::uint64_t) * std::size(kRenderCounters) + 2 * sizeof(double),
              "a RenderStats field is missing from kRenderCounters (or a non-counter was added)");

void RenderStats::add_counters(const RenderStats& o) {
  for (const RenderCounter& c : kRenderCounters) {
    std::uint64_t& mine = this->*c.field;
    const std::uint64_t theirs = o.*c.field;
    mine = c.combine == RenderCounter::Combine::Sum ? mine + theirs : std::max(mine, theirs);
  }
}

std::vector<std::string> render_warnings(const RenderStats& s) {
  std::vector<std::string> out;
  char buf[256];
  if (s.samples > 0 &&
      static_cast<double>(s.discarded_samples) > kDiscardedWarnFraction * static_cast<double>(s.samples)) {
    std::snprintf(buf, sizeof buf,
                  "%llu of %llu samples (%.3g%%) were not finite (NaN or Inf radiance) and were "
                  "discarded; the image is darker than it should be (check light sizes and "
                  "intensities)",
                  static_cast<unsigned long long>(s.discarded_samples), static_cast<unsigned long long>(s.samples),
                  100.0 * static_cast<double>(s.discarded_samples) / static_cast<double>(s.samples));
    out.emplace_back(buf);
  }
  if (s.stalled_paths > 0) {
    std::snprintf(buf, sizeof buf,
                  "%llu paths were ended by a loop guard (a step that did not advance or a step "
                  "budget exceeded) and contribute nothing past that point; see docs/physics.md "
                  "\"Loop guards\"",
                  static_cast<unsigned long long>(s.stalled_paths));
    out.emplace_back(buf);
  }
  return out;
}

}  // namespace tessera
