#pragma once
// --stats FILE.json: render statistics as a JSON object (docs/cli.md).
#include <tessera/stats.h>

#include <string>
#include <vector>

namespace tessera::job {

/// What one render did, for the statistics file.
struct RenderRecord {
  std::string name;
  int width = 0, height = 0, spp = 0;
  RenderStats stats;             ///< wall_seconds: render only (no prepare, no I/O)
  double prepare_seconds = 0.0;  ///< tessera::prepare (majorant grid, tables, tiles)
  double denoise_seconds = 0.0;  ///< tessera::denoise (image.denoise), 0 when off
  std::string device = "cpu";    ///< where it traced: "cpu" or "cuda:N" (config::device_text)
  std::vector<std::string> outputs;
  /// What may be wrong with the image (tessera::render_warnings(prepared, stats),
  /// scene_warnings.h), one sentence each; never a failure.
  std::vector<std::string> warnings;
};

/// The JSON text: the totals over `records` at top level, plus a "renders" array with one
/// object per record.
std::string stats_json(const std::vector<RenderRecord>& records);

/// Writes stats_json(records) to `path` through AtomicOutputFile (nothing under `path` unless
/// complete), creating its directory; throws naming the path.
void write_stats_json(const std::string& path, const std::vector<RenderRecord>& records);

}  // namespace tessera::job
