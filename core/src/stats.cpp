#include <tessera/stats.h>

#include <cstdio>

namespace tessera {

void RenderStats::add_counters(const RenderStats& o) {
  samples += o.samples;
  free_flight_lookups += o.free_flight_lookups;
  transmittance_lookups += o.transmittance_lookups;
  gradient_lookups += o.gradient_lookups;
  real_collisions += o.real_collisions;
  null_collisions += o.null_collisions;
  discarded_samples += o.discarded_samples;
  stalled_paths += o.stalled_paths;
  tiles_skipped += o.tiles_skipped;
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
                  static_cast<unsigned long long>(s.discarded_samples),
                  static_cast<unsigned long long>(s.samples),
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
