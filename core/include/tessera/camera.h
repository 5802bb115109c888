#pragma once
/// Pinhole / thin-lens camera (docs/physics.md "Camera").
#include <tessera/math.h>

#include <type_traits>

namespace tessera {

struct CameraDesc {
  Vec3 position{0.0, 0.0, 5.0};
  Vec3 look_at{0.0, 0.0, 0.0};
  Vec3 up{0.0, 1.0, 0.0};
  double fov_deg = 30.0;        ///< vertical field of view, (0, 180)
  double aperture = 0.0;        ///< lens radius, world units; 0 = pinhole
  double focus_distance = 0.0;  ///< 0 = |look_at - position|
};

/// Prepared camera: generates primary rays. Pixel (px, py), py = 0 the top row, covers
/// [px, px+1) x [py, py+1); (jx, jy) in [0,1)^2 pick the point in the pixel, (lx, ly) in
/// [0,1)^2 the point on the lens (concentric disk mapping).
class Camera {
 public:
  Camera() = default;
  /// Throws std::invalid_argument naming the fault: position == look_at, up parallel to the
  /// view direction or zero, fov outside (0, 180), negative aperture or focus distance,
  /// non-finite values, width or height < 1.
  Camera(const CameraDesc& desc, int width, int height);

  /// Host and device (kernel/camera_ray.h holds the one definition).
  TESSERA_HOST_DEVICE Ray generate(double px, double py, double lx, double ly) const;

  /// Pixel coordinates (px, py) of the pinhole ray through world point p; false when p is not
  /// strictly in front of the camera (then px, py are unset).
  bool project(const Vec3& p, double* px, double* py) const;
  TESSERA_HOST_DEVICE bool is_pinhole() const { return m_aperture <= 0.0; }

 private:
  Vec3 m_pos{}, m_right{}, m_up{}, m_forward{};
  double m_tan_half = 0.0, m_aspect = 1.0, m_aperture = 0.0, m_focus = 1.0;
  int m_width = 1, m_height = 1;
};
static_assert(std::is_trivially_copyable_v<Camera>);

}  // namespace tessera
