#pragma once
/// RenderSpec: one entry of `renders:`, as written in the config, fully validated.
#include <tessera/config/annotations.h>
#include <tessera/config/light_spec.h>
#include <tessera/config/point_spec.h>
#include <tessera/config/transfer_function_spec.h>
#include <tessera/image_format.h>
#include <tessera/image_io.h>
#include <tessera/integrator.h>
#include <tessera/scene.h>
#include <tessera/tiles.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tessera::config {

/// When the adapter renders: exactly one of `{every: N}`, `{at: [steps]}`, `{when: {above: X}}`.
struct TriggerSpec {
  enum class Kind { Every, At, When };
  Kind kind = Kind::Every;
  std::int64_t every = 1;        ///< Every: fires when step % every == 0; >= 1
  std::vector<std::int64_t> at;  ///< At: the steps, as given (non-empty, each >= 0)
  double above = 0.0;            ///< When: fires when the field maximum exceeds it
};

/// One entry of `camera: {keyframes: [...]}`: where the camera is at simulation step `step`.
/// Its points do not move per step (no `{start, per_step}` orbit values: the keyframes move
/// the camera); `position` may be an orbit with `distance: fit`, framed with this `fov`.
struct CameraKeyframe {
  std::int64_t step = 0;
  PointSpec position;  ///< required; differs from look_at where that is plain to see
  PointSpec look_at = PointSpec::center();
  double fov = 30.0;  ///< vertical, degrees, (0, 180)
};

/// How a keyframed camera moves between its keyframes (camera_keyframes.h).
enum class CameraInterpolation { Linear, Smooth };

struct CameraSpec {
  /// The parser's default, where the config gives neither position nor keyframes, is
  /// default_camera_position() (render_defaults.h); a default-constructed spec has `center`.
  PointSpec position;
  PointSpec look_at = PointSpec::center();
  Vec3 up{0.0, 0.0, 1.0};       ///< non-zero
  double fov = 30.0;            ///< vertical, degrees, (0, 180)
  double aperture = 0.0;        ///< >= 0
  double focus_distance = 0.0;  ///< >= 0; 0 = distance to look_at
  /// Non-empty: a keyframed camera; position, look_at and fov above are unused (the config
  /// gives either them or keyframes). Steps strictly increasing, 1 to kMaxKeyframes entries.
  std::vector<CameraKeyframe> keyframes;
  CameraInterpolation interpolation = CameraInterpolation::Linear;  ///< keyframes only
  static constexpr std::size_t kMaxKeyframes = 4096;
};

/// `integrator:`: the core IntegratorDesc plus the per-render options that live in
/// tessera::RenderOptions.
struct IntegratorSpec {
  IntegratorDesc desc;
  std::uint64_t seed = 0;
  int tile = 8;  ///< tile edge in pixels; 0 = scanline
  TileOrder tile_order = TileOrder::RowMajor;
};

/// `output: {cinema: ...}`: a Cinema image database (camera sweep) written by the adapter.
struct CinemaSpec {
  std::vector<double> azimuths;    ///< degrees
  std::vector<double> elevations;  ///< degrees, [-90, 90]
  /// Views (azimuths x elevations) one render may have: each is a whole render and image.
  static constexpr std::size_t kMaxViews = 4096;
};

struct OutputSpec {
  std::string file = "{name}_{step:06d}";                                ///< pattern, see output_path.h; no extension
  std::vector<ImageFormat> formats{ImageFormat::Exr, ImageFormat::Png};  ///< non-empty, no repeats
  double exposure = 0.0;                                                 ///< stops, PNG only
  ToneMap::Curve tonemap = ToneMap::Curve::Aces;                         ///< PNG only
  bool variance = false;                                                 ///< EXR: add the per-pixel variance channel
  bool samples = false;  ///< EXR: add the per-pixel sample-count channel
  std::optional<CinemaSpec> cinema;

  bool has_format(ImageFormat f) const;
  ToneMap tone_map() const { return ToneMap{exposure, tonemap}; }
};

/// One render. What the config leaves out is filled in by the parser: per key as
/// docs/config.md's tables say, and whole blocks (name, camera, transfer function, light,
/// background) as render_defaults.h says, so that `renders: [{field: f}]` is a complete render.
struct RenderSpec {
  std::string name;   ///< unique, [A-Za-z0-9_-]+, 1 to kMaxName; default: the field's
  std::string field;  ///< adapter: published field name; "" = not given
  /// `field: {magnitude: [a, b, c]}`: the three published fields whose Euclidean norm is
  /// rendered, per lookup (magnitude_field.h); empty for a scalar field. `field` then reads
  /// "|a, b, c|", for messages and labels only (no published field has that name to the
  /// renderer: field_key() tells the two kinds apart).
  std::vector<std::string> magnitude;
  std::optional<TriggerSpec> trigger;  ///< adapter only; absent = every step
  ImageDesc image;                     ///< width, height in [1, 16384], spp >= 1
  /// `image.min_spp`, adapter with tessera.budget: the fewest samples per pixel worth an
  /// image, in [1, image.spp]; a render the budget cannot give that many is skipped. Default 1.
  int min_spp = 1;
  CameraSpec camera;
  TransferFunctionSpec transfer_function;  ///< default: default_transfer_function()
  std::vector<LightSpec> lights;
  BackgroundSpec background;
  IntegratorSpec integrator;
  OutputSpec output;
  /// `annotations:`: a colour bar and text drawn into the PNG (never the EXR); absent = none.
  std::optional<AnnotationsSpec> annotations;

  static constexpr std::size_t kMaxName = 128;  ///< names end up in file names and every message

  /// True iff the render reads the published field `name`: its field, a component of its
  /// magnitude, or any field when it names none (the only published one).
  bool uses(const std::string& name) const;
  /// The key under which the adapter keeps what it derived from the render's field (ranges,
  /// replicas): the field's name, or for a magnitude a text no render's field name can equal.
  std::string field_key() const;
};

}  // namespace tessera::config
