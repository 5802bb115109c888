#pragma once
/// Points and lengths as written in a config, kept unresolved until the data bounds are known
/// (see build_scene.h for how they resolve).
#include <tessera/math.h>

#include <cstdint>

namespace tessera::config {

/// One value of an orbit: a plain number `S`, or `{start: S, per_step: D}`, S + D * n at
/// simulation step n (a moving camera). A plain number converts to {S, 0}.
struct OrbitValue {
  double start = 0.0;
  double per_step = 0.0;  ///< |D| <= kMaxPerStep

  constexpr OrbitValue() = default;
  constexpr OrbitValue(double s, double d = 0.0) : start(s), per_step(d) {}  // NOLINT: a number is a value
  bool operator==(const OrbitValue&) const = default;
  constexpr bool moves() const { return per_step != 0.0; }
  /// S + D * n; exactly S when D is 0.
  constexpr double at(std::int64_t step) const {
    return moves() ? start + per_step * static_cast<double>(step) : start;
  }
};

/// The largest |per_step| of an orbit value, in its key's units per step.
inline constexpr double kMaxPerStep = 1e6;
/// An orbit's elevation in degrees lies in [kMinElevation, kMaxElevation] and its distance is
/// at least kMinDistance, when the config is loaded (S) and at every step (S + D * n).
inline constexpr double kMinElevation = -90.0, kMaxElevation = 90.0;
inline constexpr double kMinDistance = 0.0;

/// `{orbit: {azimuth, elevation, distance}}`: a point on a sphere about the data centre.
/// `distance: fit` (camera.position only) sets `fit`; the distance is then computed when the
/// scene is built, from the camera's fov and the image's aspect ratio (see build_scene.h).
/// Each value may move per step (OrbitValue); at(n) is the orbit at step n, which is where
/// the scene is built from (and where the key's range is checked again).
struct OrbitSpec {
  OrbitValue azimuth = 0.0;    ///< degrees, about the camera's up axis from the reference direction
  OrbitValue elevation = 0.0;  ///< degrees, from the plane normal to up, [-90, 90]
  OrbitValue distance = 1.0;   ///< in bounding-sphere radii of the data, >= 0; unused when fit
  bool fit = false;            ///< `distance: fit`: the data's bounding sphere just fills the view

  bool moves() const { return azimuth.moves() || elevation.moves() || distance.moves(); }
  /// The orbit at simulation step n, nothing moving.
  OrbitSpec at(std::int64_t step) const { return {azimuth.at(step), elevation.at(step), distance.at(step), fit}; }
};

/// A point: `[x, y, z]` (world units), the word `center` (centre of the data bounds) or an orbit.
struct PointSpec {
  enum class Kind { Absolute, Center, Orbit };
  Kind kind = Kind::Center;
  Vec3 xyz{0.0};    ///< Absolute
  OrbitSpec orbit;  ///< Orbit

  static constexpr PointSpec absolute(const Vec3& p) { return {Kind::Absolute, p, {}}; }
  static constexpr PointSpec center() { return {Kind::Center, Vec3(0.0), {}}; }
  static constexpr PointSpec on_orbit(OrbitValue azimuth, OrbitValue elevation, OrbitValue distance) {
    return {Kind::Orbit, Vec3(0.0), {azimuth, elevation, distance, false}};
  }
  /// `{orbit: {azimuth, elevation, distance: fit}}`
  static constexpr PointSpec on_orbit_fit(OrbitValue azimuth, OrbitValue elevation) {
    return {Kind::Orbit, Vec3(0.0), {azimuth, elevation, 1.0, true}};
  }
  bool is_fit() const { return kind == Kind::Orbit && orbit.fit; }
  bool moves() const { return kind == Kind::Orbit && orbit.moves(); }
};

/// A length: a number in world units, or `{relative: r}`, r times the bounding-sphere radius.
struct LengthSpec {
  bool relative = false;
  double value = 1.0;

  static constexpr LengthSpec world(double v) { return {false, v}; }
  static constexpr LengthSpec relative_to_radius(double r) { return {true, r}; }
  double resolve(double data_radius) const { return relative ? value * data_radius : value; }
};

}  // namespace tessera::config
