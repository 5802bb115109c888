#pragma once
/// The `lights:` list and `background:` block of a render, as written.
#include <tessera/config/point_spec.h>
#include <tessera/lights.h>

#include <string>

namespace tessera::config {

struct LightSpec {
  enum class Type { Rect, Sphere };
  Type type = Type::Rect;
  PointSpec position;                   ///< required
  PointSpec target = PointSpec::center();  ///< rect: the side it emits toward
  LengthSpec width = LengthSpec::world(1.0), height = LengthSpec::world(1.0);  ///< rect `size`
  LengthSpec radius = LengthSpec::world(1.0);  ///< sphere, resolves to > 0
  Color color{1.0};                     ///< components >= 0
  double intensity = 1.0;               ///< >= 0; radiance = color * intensity
};

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
