#pragma once
/// The `lights:` list and `background:` block of a render, as written.
#include <tessera/config/point_spec.h>
#include <tessera/lights.h>

#include <string>
#include <variant>

namespace tessera::config {

/// `{type: rect, ...}`: core's RectLightDesc once its points and lengths are resolved.
struct RectLightSpec {
  PointSpec position;                      ///< required
  PointSpec target = PointSpec::center();  ///< the side it emits toward; not `position`
  LengthSpec width = LengthSpec::world(1.0), height = LengthSpec::world(1.0);  ///< `size`, > 0
  Color color{1.0};                                                            ///< components >= 0
  double intensity = 1.0;                                                      ///< >= 0; radiance = color * intensity
};

/// `{type: sphere, ...}`: core's SphereLightDesc once its centre and radius are resolved.
struct SphereLightSpec {
  PointSpec position;                          ///< required; the centre
  LengthSpec radius = LengthSpec::world(1.0);  ///< > 0
  Color color{1.0};                            ///< components >= 0
  double intensity = 1.0;                      ///< >= 0; radiance = color * intensity
};

/// One entry of `lights:`, one alternative per kind, in the order of core's LightDesc
/// (tessera/lights.h). Parsing (parse_lights.cpp), resolving (build_scene.cpp) and writing
/// back (to_yaml.cpp) visit it with one overload per kind, and the name table
/// (enum_names.h: kLightTypeNames) has one row per alternative: a new kind does not compile
/// until each of them handles it (docs/lights.md).
using LightSpec = std::variant<RectLightSpec, SphereLightSpec>;

struct BackgroundSpec {
  BackgroundType type = BackgroundType::Constant;
  Color color{0.0};                          ///< constant
  Color top{1.0}, middle{0.5}, bottom{0.0};  ///< gradient
  Vec3 up{0.0, 0.0, 1.0};                    ///< gradient and envmap
  std::string file;                          ///< envmap: EXR path, resolved against the YAML dir
  double intensity = 1.0;                    ///< >= 0
  bool visible = true;
};

}  // namespace tessera::config
