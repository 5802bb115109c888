#pragma once
/// From a validated RenderSpec to the plain tessera::SceneDesc that core renders, once the
/// data bounds and value range of the field are known.
///
/// Points: `center` is data_bounds.center(). An orbit point is
///   center + distance * R * (cos(el) (cos(az) e1 + sin(az) e2) + sin(el) up)
/// with R = data_bounds.radius(), up = the normalised camera up, e1 = the world axis least
/// aligned with up (x, then y, then z on ties) projected onto the plane normal to up and
/// normalised, e2 = cross(up, e1). For up = +z: e1 = +x, e2 = +y, so azimuth 90 is +y.
/// Lights resolve their orbit points with the camera's up too.
///
/// `distance: fit` (camera.position only) puts the camera at fit_distance(fov, width, height)
/// radii: the data's bounding sphere is then tangent to the frustum planes of the smaller of
/// the two fields of view, so the whole data fills that direction of the image without being
/// cut, and the other direction has room to spare. The framing assumes look_at is `center`
/// (the default); the aperture of a thin-lens camera does not change it.
/// Lengths `{relative: r}` resolve to r * R; a density scale `{optical_depth: t}` to
/// t / (2 R) per world unit (resolve_density_scale).
#include <tessera/config/config.h>
#include <tessera/config/render_spec.h>
#include <tessera/image.h>
#include <tessera/scene.h>

#include <cstdint>
#include <memory>
#include <utility>

namespace tessera::config {

/// The unit direction of an orbit point about `up` (see above). `up` need not be normalised
/// but must be non-zero. An azimuth beyond about 5.7e307 degrees (whose radians overflow) is
/// reduced modulo 360 first, exactly, so every finite azimuth gives a finite direction. The orbit must not move (take OrbitSpec::at(step) of one that does);
/// a moving one throws std::logic_error, as resolve_point does for a moving orbit point.
Vec3 orbit_direction(const OrbitSpec& orbit, const Vec3& up);

/// `distance: fit` in bounding-sphere radii: 1 / sin(h), h = half the smaller field of view;
/// the vertical one is fov_deg, the horizontal one 2 atan(tan(fov_deg / 2) width / height).
/// Throws std::invalid_argument for a fov outside (0, 180) or an image smaller than 1x1.
double fit_distance(double fov_deg, int width, int height);

/// Resolves a point against the data bounds; `up` is the camera up used by orbits.
/// Throws std::logic_error for a `distance: fit` orbit (use the overload below).
Vec3 resolve_point(const PointSpec& p, const Bounds& data_bounds, const Vec3& up);

/// As above; an orbit with `distance: fit` is put at `fit_radii` bounding-sphere radii.
Vec3 resolve_point(const PointSpec& p, const Bounds& data_bounds, const Vec3& up, double fit_radii);

/// The TF range, with `auto` replaced by auto_range; an empty auto range (lo == hi, e.g. a
/// constant field) is widened to [lo - 0.5, hi + 0.5], or by 2^-40 |lo| each way where 0.5
/// would vanish in rounding (|lo| > 2^39), so that lo < hi always holds.
std::pair<double, double> resolve_range(const RangeSpec& r, std::pair<double, double> auto_range);

/// Core transfer function; colormap names are expanded (colormaps.h). A density scale
/// relative to the data (`{optical_depth: t}`, `auto`) needs the data's extent: here it is
/// t, as for data whose diagonal is 1; build_scene sets resolve_density_scale's value.
TransferFunction build_transfer_function(const TransferFunctionSpec& tf, std::pair<double, double> auto_range);

/// The extinction scale of `tf` per world unit (sigma_t = scale * opacity(u)): density_scale
/// as written, or, for `{optical_depth: t}` and `auto`, t / |hi - lo| with |hi - lo| the data
/// bounds' diagonal, so the diagonal has optical depth t at opacity 1 whatever the data's
/// length unit (data 1000 times larger in world units gets 1/1000 of the scale). Throws
/// std::invalid_argument naming the key for a relative scale on data of no extent (a single
/// vertex) or one whose scale is not finite (a diagonal below about t / 1e308).
double resolve_density_scale(const TransferFunctionSpec& tf, const Bounds& data_bounds);

/// Reads the background's envmap EXR (tessera::read_exr); nullptr unless type is envmap.
/// Throws std::runtime_error naming the file.
std::shared_ptr<const Image> load_envmap(const BackgroundSpec& bg);

/// Everything but the field: camera, lights, TF, background, integrator, image, options.
/// options.threads is 0 (use build_render_options to fill it from the global options).
/// Reads the envmap (if any) from disk on every call. `step` is the simulation step: a
/// moving orbit (`{start: S, per_step: D}`) is placed at S + D * step, and a value that
/// leaves its key's range there (elevation outside [-90, 90], distance below 0) throws
/// std::invalid_argument naming the render, the key and the step. A keyframed camera
/// (`camera.keyframes`) is placed at its pose of `step` (camera_keyframes.h); a pose that makes
/// no camera there (position on look_at, a view along up) throws std::invalid_argument naming
/// the render, the step and its keyframes.
SceneDesc build_scene(const RenderSpec& spec, const Bounds& data_bounds, std::pair<double, double> auto_range,
                      const VolumeGeometry& geom, std::int64_t step = 0);

/// As above with an envmap already loaded by load_envmap (callers rendering many frames load
/// it once). `envmap` is ignored unless the background type is envmap, where it must be set.
SceneDesc build_scene(const RenderSpec& spec, const Bounds& data_bounds, std::pair<double, double> auto_range,
                      const VolumeGeometry& geom, std::shared_ptr<const Image> envmap, std::int64_t step = 0);

/// seed, tile and tile order from the render's integrator block, threads from the global
/// options; frame = 0.
RenderOptions build_render_options(const RenderSpec& spec, const GlobalOptions& global);

}  // namespace tessera::config
