#pragma once
/// Area lights and the background light (physics spec section 4). Lights are transparent
/// emitters: they add radiance to the rays that meet their front side and occlude nothing.
#include <tessera/image.h>
#include <tessera/math.h>

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace tessera {

/// One-sided rectangle centred at `position`, emitting toward `target`. Frame: normal
/// n = normalize(target - position); u = normalize(cross(ref, n)) with ref = +z, or +y when
/// |n.z| > 0.999; v = cross(n, u). `width` runs along u, `height` along v.
struct RectLightDesc {
  Vec3 position{0.0};
  Vec3 target{0.0, 0.0, -1.0};
  double width = 1.0, height = 1.0;
  Color radiance{1.0};  ///< color * intensity, W / (m^2 sr), constant over the surface
};

/// Sphere emitting constant radiance outward from its surface.
struct SphereLightDesc {
  Vec3 center{0.0};
  double radius = 1.0;
  Color radiance{1.0};
};

/// The light kinds, one alternative each: the one central list. The kernels' light set keeps
/// this order (every rect light, then every sphere light, whatever the order of
/// SceneDesc::lights), so images do not depend on how a config interleaves kinds. A new kind:
/// its description here and its alternative below; its kernel file (core/src/lights/, see
/// area_lights.h); on the config side its spec alternative, its table row and its parse,
/// resolve and write-back overloads (docs/lights.md lists every file).
using LightDesc = std::variant<RectLightDesc, SphereLightDesc>;

enum class BackgroundType { Constant, Gradient, EnvMap };

struct BackgroundDesc {
  BackgroundType type = BackgroundType::Constant;
  Color color{0.0};                          ///< Constant
  Color top{1.0}, middle{0.5}, bottom{0.0};  ///< Gradient, by dot(direction, up)
  Vec3 up{0.0, 0.0, 1.0};                    ///< Gradient and EnvMap "up" (envmap pole)
  double intensity = 1.0;                    ///< multiplies every type
  bool visible = true;                       ///< false: hidden from camera rays only
  std::shared_ptr<const Image> envmap;       ///< EnvMap: equirectangular, linear RGB
};

}  // namespace tessera
