// The defaults of a render that gives only a field (render_defaults.h).
#include <tessera/config/render_defaults.h>

#include <algorithm>

namespace tessera::config {
namespace {

/// Render names: letters, digits, `_` and `-`, at most this many (parse_render.cpp checks it).
constexpr std::size_t kMaxDefaultName = 128;

bool name_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

}  // namespace

PointSpec default_camera_position() { return PointSpec::on_orbit_fit(35.0, 25.0); }

std::vector<ScalarPoint> default_opacity() { return {{0.0, 0.0}, {0.5, 0.2}, {1.0, 1.0}}; }

TransferFunctionSpec default_transfer_function() {
  TransferFunctionSpec tf;
  tf.range = RangeSpec{true, 0.0, 1.0};
  tf.density_scale = kDefaultOpticalDepth;
  tf.density_relative = true;
  tf.opacity = default_opacity();
  tf.diffuse = ColorTFSpec{"viridis", {}};
  return tf;
}

std::vector<LightSpec> default_lights() {
  RectLightSpec key;
  key.position = PointSpec::on_orbit(-30.0, 50.0, 3.0);
  key.target = PointSpec::center();
  key.width = key.height = LengthSpec::relative_to_radius(1.5);
  key.color = Color(1.0, 0.96, 0.9);
  key.intensity = 60.0;
  return {key};
}

BackgroundSpec default_background() {
  BackgroundSpec b;
  b.type = BackgroundType::Gradient;
  b.top = Color(0.3, 0.36, 0.5);
  b.middle = Color(0.07, 0.075, 0.09);
  b.bottom = Color(0.02, 0.02, 0.025);
  return b;
}

std::string default_render_name(const std::string& field) {
  if (field.empty()) return "render";
  std::string name = field.substr(0, kMaxDefaultName);
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !name_char(c); }, '_');
  return name;
}

}  // namespace tessera::config
