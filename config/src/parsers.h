#pragma once
// Private: one parse function per block of the schema. Each takes the block's Value and
// returns a fully validated spec or throws ConfigError.
#include <tessera/config/config.h>

#include "yaml_reader.h"

#include <functional>
#include <string>

namespace tessera::config::detail {

GlobalOptions parse_global(const Value& v);
VolumeSpec parse_volume(const Value& v);
/// One render; `unique_name(field)` names a render that gives no name (unique in the file).
RenderSpec parse_render(const Value& v, const std::function<std::string(const std::string&)>& unique_name);
TriggerSpec parse_trigger(const Value& v);
CameraSpec parse_camera(const Value& v);
OutputSpec parse_output(const Value& v);
/// `annotations:` of render `r` (its image, field and TF already parsed): also checks that
/// everything fits in the image, with the font, at load time.
AnnotationsSpec parse_annotations(const Value& v, const RenderSpec& r);
/// `allow_fit`: whether an orbit may say `distance: fit` (camera.position only).
PointSpec parse_point(const Value& v, bool allow_fit = false);
/// A number or `{relative: r}`, resolving to > 0 (strictly_positive) or >= 0.
LengthSpec parse_length(const Value& v, bool strictly_positive);
/// For messages, from the keys parse_point and parse_length accept: what a point may be,
/// `[x, y, z], center or {orbit: {azimuth, elevation, distance}}`, and a length written as a
/// mapping, `{relative: r}`.
std::string point_allowed();
std::string length_map_allowed();
/// Whether two points are the same before the data bounds are known: both `center`, or the
/// same `[x, y, z]` (a camera looking at its position, a rect light aimed at itself).
bool plainly_same(const PointSpec& a, const PointSpec& b);
TransferFunctionSpec parse_transfer_function(const Value& v);
LightSpec parse_light(const Value& v);
BackgroundSpec parse_background(const Value& v);
IntegratorSpec parse_integrator(const Value& v);

/// A file name from the config, resolved against the document's base directory and made
/// absolute; the file must exist.
std::string resolve_existing_file(const Value& v);

}  // namespace tessera::config::detail
