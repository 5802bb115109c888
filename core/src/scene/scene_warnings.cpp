#include <tessera/scene_warnings.h>

#include <tessera/number_text.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tessera {
namespace {

std::string interval(double lo, double hi) { return "[" + short_number(lo) + ", " + short_number(hi) + "]"; }

/// The axes along which the bounds have no extent ("x", "y and z"; "" when none): a volume
/// one vertex thick there has no thickness, so nothing in it absorbs or scatters light.
std::string flat_axes(const Bounds& b) {
  std::string names;
  for (int a = 0; a < 3; ++a)
    if (b.lo[a] == b.hi[a]) names += char('x' + a);
  if (names.size() < 2) return names;
  std::string axes;
  for (std::size_t i = 0; i < names.size(); ++i)
    axes += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + std::string(1, names[i]);
  return axes;
}

/// The warning for flat data, naming its extent, or "".
std::string flat_data(const Bounds& b) {
  const std::string axes = flat_axes(b);
  if (axes.empty()) return "";
  const std::string where = "the data's bounds (" + interval(b.lo.x, b.hi.x) + " x " + interval(b.lo.y, b.hi.y) +
                            " x " + interval(b.lo.z, b.hi.z) + ")";
  if (b.lo == b.hi) return where + " are a single point (the volume has one vertex)";
  return where + " have no extent along " + axes +
         " (the volume is one vertex thick there, so it has no "
         "thickness to absorb or scatter light; give it at least 2 vertices along every axis)";
}

/// What the transfer function makes of the data's finite values.
struct TfVerdict {
  bool disjoint = false;   ///< transfer_function.range misses [vmin, vmax]
  bool invisible = false;  ///< sigma_t = 0 for every finite value of the data
  double max_opacity = 0.0;
};

TfVerdict judge_tf(const TransferFunction& tf, double vmin, double vmax) {
  TfVerdict v;
  v.disjoint = vmax < tf.lo || vmin > tf.hi;
  const double u0 = tf.normalise(vmin), u1 = tf.normalise(vmax);
  v.max_opacity = tf.opacity.max_over(std::min(u0, u1), std::max(u0, u1));
  v.invisible = !(tf.density_scale * v.max_opacity > 0.0);
  return v;
}

/// Where the data's bounds lie for the camera (pinhole projection of the eight corners, with
/// no absolute epsilon so that boxes of any scale are judged alike).
enum class View { In, Behind, Outside, SubPixel };

View camera_view(const SceneDesc& desc, const Bounds& b) {
  const CameraDesc& c = desc.camera;
  const Vec3 f = glm::normalize(c.look_at - c.position);
  const Vec3 r = glm::normalize(glm::cross(f, c.up));
  const Vec3 u = glm::cross(r, f);
  const double ty = std::tan(0.5 * c.fov_deg * M_PI / 180.0);
  const double tx = ty * double(desc.image.width) / double(desc.image.height);
  int in_front = 0;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Vec3 p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
    const Vec3 v = p - c.position;
    const double z = glm::dot(v, f);
    if (!(z > 0.0)) continue;
    ++in_front;
    const double sx = glm::dot(v, r) / z, sy = glm::dot(v, u) / z;
    x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
  }
  if (in_front == 0) return View::Behind;
  if (in_front < 8) return View::In;  // the box straddles the camera plane: part of it may show
  if (x1 < -tx || x0 > tx || y1 < -ty || y0 > ty) return View::Outside;
  // Pixels covered by the projected box (clipped to the image)
  const double px = (std::min(x1, tx) - std::max(x0, -tx)) / (2.0 * tx) * desc.image.width;
  const double py = (std::min(y1, ty) - std::max(y0, -ty)) / (2.0 * ty) * desc.image.height;
  if (!(px * py >= 1.0)) return View::SubPixel;
  return View::In;
}

/// "" when the data is (possibly) in view, else why not, naming the bounds.
std::string camera_misses(const SceneDesc& desc, const Bounds& b) {
  const View v = camera_view(desc, b);
  if (v == View::In) return "";
  const std::string where = "the data's bounds (" + interval(b.lo.x, b.hi.x) + " x " + interval(b.lo.y, b.hi.y) +
                            " x " + interval(b.lo.z, b.hi.z) + ")";
  if (v == View::Behind) return where + " are behind the camera (camera.look_at points away from them)";
  if (v == View::Outside) return where + " are outside the camera's view (camera.look_at or fov misses them)";
  return where + " cover less than one pixel of the image (camera too far or fov too wide)";
}

}  // namespace

std::vector<std::string> scene_warnings(const PreparedScene& scene) {
  std::vector<std::string> out;
  const FieldSummary& s = *scene.summary();
  const SceneDesc& desc = scene.desc();
  const std::uint64_t vertices = s.element_count();  // every level's samples for a hierarchy

  // The data: no finite value, NaN holes, one value everywhere
  if (!s.has_finite()) {
    out.push_back("the field has no finite value (" + std::to_string(s.nan_vertices()) + " of " +
                  std::to_string(vertices) + " vertices are NaN, the rest +-Inf): nothing of it is visible");
    return out;
  }
  if (s.nan_vertices() > 0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g%%",
                  100.0 * double(s.nan_vertices()) / double(std::max<std::uint64_t>(1, vertices)));
    out.push_back(std::to_string(s.nan_vertices()) + " of " + std::to_string(vertices) + " vertices (" + buf +
                  ") are NaN: there is no medium around them (holes in the image)");
  }
  const double vmin = s.value_min(), vmax = s.value_max();
  if (vmin == vmax)
    out.push_back("the field is constant (" + short_number(vmin) +
                  ") at every finite vertex: the image shows at most a uniform block, nothing of its structure "
                  "(a simulation's first step before anything happened?)");

  // The transfer function against the data's values
  const TransferFunction& tf = desc.tf;
  const TfVerdict v = judge_tf(tf, vmin, vmax);
  const std::string data = vmin == vmax ? "value " + short_number(vmin) : "values " + interval(vmin, vmax);
  if (v.disjoint) {
    out.push_back("transfer_function.range " + interval(tf.lo, tf.hi) + " misses the data's " + data +
                  (v.invisible ? ": nothing of the field is visible"
                               : ": every value maps to the same end of the transfer functions (a uniform block)") +
                  " (set the range within the data's, or range: auto)");
  } else if (v.invisible) {
    out.push_back("the opacity transfer function is 0 over the data's " + data + " (u in " +
                  interval(tf.normalise(vmin), tf.normalise(vmax)) + " of transfer_function.range " +
                  interval(tf.lo, tf.hi) + "): nothing of the field is visible");
  }

  // Flat data, else the camera against the data's bounds (flat data is never in view: the
  // camera is not to blame)
  const std::string flat = flat_data(scene.bounds());
  const std::string cam = flat.empty() ? camera_misses(desc, scene.bounds()) : flat;
  if (!cam.empty()) out.push_back(cam + ": nothing of the field is visible");
  return out;
}

std::vector<std::string> render_warnings(const PreparedScene& scene, const RenderStats& stats) {
  std::vector<std::string> out = scene_warnings(scene);
  for (std::string& w : render_warnings(stats)) out.push_back(std::move(w));
  if (stats.samples == 0 || stats.real_collisions > 0) return out;

  // No real collision at all: name the likely cause, first that applies
  const FieldSummary& s = *scene.summary();
  const SceneDesc& desc = scene.desc();
  std::string cause;
  if (!s.has_finite()) {
    cause = "the field has no finite value";
  } else {
    const TfVerdict v = judge_tf(desc.tf, s.value_min(), s.value_max());
    const Bounds b = scene.bounds();
    const double depth = desc.tf.density_scale * v.max_opacity * 2.0 * b.radius();
    if (!flat_axes(b).empty()) cause = "the data has no extent along " + flat_axes(b) + " (one vertex thick)";
    else if (v.disjoint) cause = "transfer_function.range misses the data's values";
    else if (v.invisible) cause = "the opacity transfer function is 0 over the data's values";
    else if (!camera_misses(desc, b).empty())
      cause = "the camera does not see the data (behind it, outside its view or under a pixel)";
    else if (depth < kThinVolumeDepth)
      cause = "transfer_function.density_scale too small (optical depth at most " + short_number(depth) +
              " across the volume: density_scale " + short_number(desc.tf.density_scale) + " x opacity " +
              short_number(v.max_opacity) + " x diagonal " + short_number(2.0 * b.radius()) + ")";
    else cause = "unclear; check transfer_function.range and opacity, density_scale and the camera";
  }
  out.push_back("nothing of the field is visible: 0 real collisions in " + std::to_string(stats.samples) +
                " samples; likely cause: " + cause);
  return out;
}

}  // namespace tessera
