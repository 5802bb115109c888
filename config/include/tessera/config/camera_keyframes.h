#pragma once
/// A keyframed camera (`camera: {keyframes: [...]}`) between its keyframes, once each keyframe
/// is resolved against the data bounds (build_scene.h resolves them, then calls these).
///
/// At simulation step n the camera is between keyframe i (the last one at or before n) and
/// keyframe i + 1, at the fraction t = (n - s_i) / (s_{i+1} - s_i) of the way; before the first
/// keyframe and after the last it holds that keyframe's pose. At a keyframe's own step the pose
/// is that keyframe's, bit for bit (t == 0 and nothing is computed).
///
/// Where both keyframes of a segment place the camera on an orbit, the segment moves along the
/// orbit: azimuth, elevation and distance (in radii; `distance: fit` counts as that keyframe's
/// fit distance) are interpolated, as numbers, and the point is placed from them as a static
/// orbit is (so 0 to 360 degrees of azimuth is a full turn, and halfway between azimuth 0 and
/// 90 is the orbit at 45). Any other segment moves in a straight line (or spline) in world space.
///
/// - `linear`: position, look_at and fov each (1 - t) a + t b, along straight lines (orbit
///   values likewise).
/// - `smooth`: a Catmull-Rom spline through the keyframes, per component of position and look_at
///   (cubic Hermite with the tangent at keyframe k from its neighbours, (p_{k+1} - p_{k-1}) /
///   (s_{k+1} - s_{k-1}) per step, so uneven keyframe spacing does not kink the path; at the first
///   and last keyframe the tangent is the secant of their one segment). The path is C1: no jerk
///   in speed or direction as the camera passes a keyframe. The fov follows the same curve,
///   clamped to the range of its segment's two keyframes, so it never leaves (0, 180). Between
///   two keyframes only, smooth and linear are the same. Orbit values follow the same spline
///   (a neighbour that is not an orbit counts as missing), the elevation and distance clamped
///   like the fov.
#include <tessera/config/render_spec.h>
#include <tessera/math.h>

#include <cstddef>
#include <cstdint>
#include <span>

namespace tessera::config {

/// A keyframe resolved against the data: world points, vertical fov in degrees; for a position
/// on an orbit also its azimuth, elevation (degrees) and distance (radii, a fit resolved).
struct CameraPose {
  Vec3 position{0.0};
  Vec3 look_at{0.0};
  double fov = 30.0;
  bool on_orbit = false;
  Vec3 orbit{0.0};  ///< on_orbit: (azimuth, elevation, distance)
  bool operator==(const CameraPose&) const = default;
};

/// Where step n falls: keyframe `i`, and the fraction `t` in [0, 1] of the way to keyframe i + 1
/// (0 before the first keyframe, at or after the last, and at a keyframe's own step).
struct KeyframeSpan {
  std::size_t i = 0;
  double t = 0.0;
};

/// `steps`: the keyframes' steps, strictly increasing, non-empty. Exact for any two int64 steps
/// (differences in unsigned arithmetic; t rounds only when they pass 2^53). O(log n).
KeyframeSpan keyframe_span(std::span<const std::int64_t> steps, std::int64_t step);

/// The keyframes around a segment: pose[1], pose[2] are keyframes i and i + 1; pose[0] is i - 1
/// (when has_before) and pose[3] is i + 2 (when has_after), which only `smooth` reads.
struct PoseWindow {
  CameraPose pose[4];
  std::int64_t step[4] = {0, 0, 0, 0};
  bool has_before = false;
  bool has_after = false;
};

/// The pose at fraction t in [0, 1] from pose[1] to pose[2] (see above). Finite poses give a
/// finite pose. When pose[1] and pose[2] are both on an orbit the result is on_orbit with the
/// interpolated orbit values, and its `position` is only the world-space estimate: the caller
/// places the point from `orbit` (build_scene does, as for a static orbit).
CameraPose interpolate_pose(CameraInterpolation mode, const PoseWindow& w, double t);

}  // namespace tessera::config
