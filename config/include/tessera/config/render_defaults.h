#pragma once
/// What a render gets for the blocks it leaves out: `renders: [{field: f}]` alone is a framed,
/// lit, coloured picture whose look does not depend on the data's length unit
/// (docs/config.md, "The smallest config"). One place for these values: the parser fills them
/// in, the effective config (to_yaml) writes them out, the docs quote them.
///
/// Which default applies when:
/// - `name` left out: the field's name (default_render_name), made unique in the file;
/// - `camera` or `camera.position` left out: default_camera_position(), an orbit framed with
///   `distance: fit`, so every unit and extent frames alike;
/// - `transfer_function` left out: default_transfer_function(), whose extinction is relative
///   to the data's diagonal; then also `lights` and `background`, where they are left out,
///   are default_lights() and default_background(), placed and sized relative to the data.
///   A render that gives its own transfer_function keeps the per-key defaults of
///   docs/config.md (no lights, a black background, density_scale 1 per world unit), as
///   configs written before these defaults existed expect;
/// - `opacity` left out of a given transfer_function: default_opacity().
#include <tessera/config/light_spec.h>
#include <tessera/config/point_spec.h>
#include <tessera/config/transfer_function_spec.h>

#include <string>
#include <vector>

namespace tessera::config {

/// `density_scale: auto`, the default transfer function's extinction: `{optical_depth: 16}`,
/// an optical depth of 16 along the data's diagonal where the opacity is 1 (9.2 along an
/// axis through a cube's centre). With default_opacity a value halfway up the range (opacity
/// 0.2) reaches one mean free path in a fifth of the diagonal, the low values stay haze and
/// the top of the range is a surface.
inline constexpr double kDefaultOpticalDepth = 16.0;

/// The camera position of a render that gives none: a three-quarter view from above,
/// `{orbit: {azimuth: 35, elevation: 25, distance: fit}}` about the camera's up.
PointSpec default_camera_position();

/// `opacity` where a transfer function gives none: `[[0, 0], [0.5, 0.2], [1, 1]]`, clear at the
/// bottom of the range, rising slowly through the middle and steeply to opaque at the top, so
/// that high values show as shapes inside a faint haze of the lower ones.
std::vector<ScalarPoint> default_opacity();

/// The transfer function of a render that gives none: `range: auto`,
/// `density_scale: {optical_depth: kDefaultOpticalDepth}`, default_opacity(), `diffuse: viridis`.
TransferFunctionSpec default_transfer_function();

/// The key light of the default look: one rect light above and to the left of the default
/// camera, `{type: rect, position: {orbit: {azimuth: -30, elevation: 50, distance: 3}},
/// target: center, size: {relative: 1.5}, color: [1, 0.96, 0.9], intensity: 60}` (its
/// irradiance at the data's centre is about 60 * 1.5^2 / 3^2 = 15, whatever the unit).
std::vector<LightSpec> default_lights();

/// The background of the default look: a dark gradient, a blue-grey sky over a near-black
/// ground, `{type: gradient, top: [0.3, 0.36, 0.5], middle: [0.07, 0.075, 0.09],
/// bottom: [0.02, 0.02, 0.025]}` (up: +z), which also fills the shadows.
BackgroundSpec default_background();

/// The name of a render that gives none: its field's name with every character other than
/// letters, digits, `_` and `-` replaced by `_`, cut to 128 characters; `render` without a
/// field. parse_config then makes it unique in the file by appending `_2`, `_3`, ...
std::string default_render_name(const std::string& field);

}  // namespace tessera::config
