#pragma once
/// Points and lengths as written in a config, kept unresolved until the data bounds are known
/// (see build_scene.h for how they resolve).
#include <tessera/math.h>

namespace tessera::config {

/// `{orbit: {azimuth, elevation, distance}}`: a point on a sphere about the data centre.
/// `distance: fit` (camera.position only) sets `fit`; the distance is then computed when the
/// scene is built, from the camera's fov and the image's aspect ratio (see build_scene.h).
struct OrbitSpec {
  double azimuth = 0.0;    ///< degrees, about the camera's up axis from the reference direction
  double elevation = 0.0;  ///< degrees, from the plane normal to up, [-90, 90]
  double distance = 1.0;   ///< in bounding-sphere radii of the data, >= 0; unused when fit
  bool fit = false;        ///< `distance: fit`: the data's bounding sphere just fills the view
};

/// A point: `[x, y, z]` (world units), the word `center` (centre of the data bounds) or an orbit.
struct PointSpec {
  enum class Kind { Absolute, Center, Orbit };
  Kind kind = Kind::Center;
  Vec3 xyz{0.0};    ///< Absolute
  OrbitSpec orbit;  ///< Orbit

  static constexpr PointSpec absolute(const Vec3& p) { return {Kind::Absolute, p, {}}; }
  static constexpr PointSpec center() { return {Kind::Center, Vec3(0.0), {}}; }
  static constexpr PointSpec on_orbit(double azimuth, double elevation, double distance) {
    return {Kind::Orbit, Vec3(0.0), {azimuth, elevation, distance, false}};
  }
  /// `{orbit: {azimuth, elevation, distance: fit}}`
  static constexpr PointSpec on_orbit_fit(double azimuth, double elevation) {
    return {Kind::Orbit, Vec3(0.0), {azimuth, elevation, 1.0, true}};
  }
  bool is_fit() const { return kind == Kind::Orbit && orbit.fit; }
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
