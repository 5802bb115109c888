#pragma once
/// The `transfer_function:` block of a render, as written (range unresolved, colormaps named).
#include <tessera/math.h>

#include <string>
#include <vector>

namespace tessera::config {

struct ScalarPoint {
  double u = 0.0;  ///< normalised value in [0, 1]
  double v = 0.0;
};

struct ColorPoint {
  double u = 0.0;
  Color c{0.0};
};

/// A colour TF: either explicit points or a colormap name (see colormaps.h); never both.
struct ColorTFSpec {
  std::string colormap;            ///< non-empty: a colormap name, `points` is empty
  std::vector<ColorPoint> points;  ///< explicit points, u non-decreasing, at most 64
  bool present() const { return !colormap.empty() || !points.empty(); }
};

/// `range: [lo, hi]` or `range: auto` (the field's min and max at render time).
struct RangeSpec {
  bool automatic = true;      ///< the default when `range` is not given
  double lo = 0.0, hi = 1.0;  ///< lo < hi when not automatic
};

struct TransferFunctionSpec {
  RangeSpec range;
  /// >= 0. As written (`density_scale: 20`): the extinction per world unit at opacity 1.
  /// With density_relative (`density_scale: {optical_depth: t}`, or `auto` for
  /// t = kDefaultOpticalDepth, render_defaults.h): t, the optical depth of the data's diagonal
  /// at opacity 1; build_scene resolves it to t / diagonal per world unit
  /// (resolve_density_scale), so the look does not depend on the data's length unit.
  double density_scale = 1.0;
  bool density_relative = false;
  /// At least one point; values >= 0. The parser fills in default_opacity() where the config
  /// gives none (render_defaults.h); a default-constructed spec has none.
  std::vector<ScalarPoint> opacity;
  ColorTFSpec diffuse;                 ///< absent: constant white (core default); values in [0, 1]
  ColorTFSpec specular;                ///< absent: zero; values in [0, 1]
  std::vector<ScalarPoint> roughness;  ///< absent: constant 0.5 (core default); values in [0, 1]
  ColorTFSpec emission;                ///< absent: zero; values >= 0
};

}  // namespace tessera::config
