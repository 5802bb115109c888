// A keyframed camera between its keyframes: where a step falls, and the pose there.
#include <tessera/config/camera_keyframes.h>

#include <algorithm>
#include <stdexcept>

namespace tessera::config {
namespace {

/// b - a for a <= b, exact in unsigned arithmetic (it may pass INT64_MAX).
std::uint64_t distance(std::int64_t a, std::int64_t b) {
  return static_cast<std::uint64_t>(b) - static_cast<std::uint64_t>(a);
}

/// (b - a) / (d - c), both spans non-negative, d > c: a ratio of step differences.
double ratio(std::int64_t a, std::int64_t b, std::int64_t c, std::int64_t d) {
  return static_cast<double>(distance(a, b)) / static_cast<double>(distance(c, d));
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return (1.0 - t) * a + t * b; }

/// The cubic Hermite curve from p1 to p2 with end tangents d1, d2 (already in units per
/// segment), at t.
template <class T>
T hermite(const T& p1, const T& d1, const T& p2, const T& d2, double t) {
  const double t2 = t * t, t3 = t2 * t;
  return (2.0 * t3 - 3.0 * t2 + 1.0) * p1 + (t3 - 2.0 * t2 + t) * d1 + (-2.0 * t3 + 3.0 * t2) * p2 + (t3 - t2) * d2;
}

/// The Catmull-Rom tangents at keyframes i and i + 1, per segment: (p_{k+1} - p_{k-1}) scaled
/// from its two segments' steps to this one's; the secant where a neighbour is missing.
template <class T>
void tangents(const PoseWindow& w, T (*get)(const CameraPose&), T& d1, T& d2) {
  const T secant = get(w.pose[2]) - get(w.pose[1]);
  d1 = w.has_before ? (get(w.pose[2]) - get(w.pose[0])) * ratio(w.step[1], w.step[2], w.step[0], w.step[2]) : secant;
  d2 = w.has_after ? (get(w.pose[3]) - get(w.pose[1])) * ratio(w.step[1], w.step[2], w.step[1], w.step[3]) : secant;
}

/// The Catmull-Rom tangents of the orbit values: a neighbour counts only when it is on an orbit.
void orbit_tangents(const PoseWindow& w, Vec3& d1, Vec3& d2) {
  PoseWindow o = w;
  o.has_before = w.has_before && w.pose[0].on_orbit;
  o.has_after = w.has_after && w.pose[3].on_orbit;
  tangents(
      o, +[](const CameraPose& p) { return p.orbit; }, d1, d2);
}

Vec3 position_of(const CameraPose& p) { return p.position; }
Vec3 look_at_of(const CameraPose& p) { return p.look_at; }
double fov_of(const CameraPose& p) { return p.fov; }

}  // namespace

KeyframeSpan keyframe_span(std::span<const std::int64_t> steps, std::int64_t step) {
  if (steps.empty()) throw std::invalid_argument("keyframe_span: no keyframes");
  // The first keyframe after the step: before the first or at/after the last, the camera holds
  const auto after = std::upper_bound(steps.begin(), steps.end(), step);
  if (after == steps.begin()) return {0, 0.0};
  const std::size_t i = static_cast<std::size_t>(after - steps.begin()) - 1;
  if (after == steps.end() || steps[i] == step) return {i, 0.0};
  return {i, ratio(steps[i], step, steps[i], steps[i + 1])};
}

CameraPose interpolate_pose(CameraInterpolation mode, const PoseWindow& w, double t) {
  const CameraPose& a = w.pose[1];
  const CameraPose& b = w.pose[2];
  if (t == 0.0) return a;
  if (t == 1.0) return b;
  const bool orbit = a.on_orbit && b.on_orbit;
  if (mode == CameraInterpolation::Linear) {
    CameraPose p{lerp(a.position, b.position, t), lerp(a.look_at, b.look_at, t), (1.0 - t) * a.fov + t * b.fov};
    if (orbit) {
      p.on_orbit = true;
      p.orbit = lerp(a.orbit, b.orbit, t);
    }
    return p;
  }

  // Smooth: one Hermite segment per value, the fov (and an orbit's elevation and distance)
  // kept between its two keyframes
  CameraPose p;
  Vec3 d1, d2;
  if (orbit) {
    orbit_tangents(w, d1, d2);
    p.on_orbit = true;
    p.orbit = hermite(a.orbit, d1, b.orbit, d2, t);
    p.orbit.y = std::clamp(p.orbit.y, std::min(a.orbit.y, b.orbit.y), std::max(a.orbit.y, b.orbit.y));
    p.orbit.z = std::clamp(p.orbit.z, std::min(a.orbit.z, b.orbit.z), std::max(a.orbit.z, b.orbit.z));
  }
  tangents(w, position_of, d1, d2);
  p.position = hermite(a.position, d1, b.position, d2, t);
  tangents(w, look_at_of, d1, d2);
  p.look_at = hermite(a.look_at, d1, b.look_at, d2, t);
  double f1 = 0.0, f2 = 0.0;
  tangents(w, fov_of, f1, f2);
  p.fov = std::clamp(hermite(a.fov, f1, b.fov, f2, t), std::min(a.fov, b.fov), std::max(a.fov, b.fov));
  return p;
}

}  // namespace tessera::config
