#include "scene/tile_culling.h"

#include <algorithm>
#include <cmath>

namespace tessera {
namespace {

struct ScreenBox {
  double x0, y0, x1, y1;
};

/// Screen rectangle covering the box [lo, hi]; false if some corner is not in front.
bool project_box(const Camera& cam, const Vec3& lo, const Vec3& hi, ScreenBox* out) {
  ScreenBox b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (int c = 0; c < 8; ++c) {
    const Vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    double px, py;
    if (!cam.project(p, &px, &py)) return false;
    b.x0 = std::min(b.x0, px);
    b.y0 = std::min(b.y0, py);
    b.x1 = std::max(b.x1, px);
    b.y1 = std::max(b.y1, py);
  }
  *out = b;
  return true;
}

}  // namespace

std::vector<std::uint8_t> cull_tiles(const PreparedSceneImpl& p) {
  std::vector<std::uint8_t> culled(p.tiles.size(), 0);
  if (!p.desc.integrator.culling || !p.camera.is_pinhole()) return culled;
  // World boxes of everything a camera ray can meet besides the background.
  std::vector<std::pair<Vec3, Vec3>> boxes;
  if (p.grid.max_majorant() > 0.0) boxes.emplace_back(p.bounds.lo, p.bounds.hi);
  for (const Light& l : p.lights) {
    if (l.infinite()) continue;  // the background: what culled tiles are filled with
    Vec3 lo, hi;
    l.bounds(&lo, &hi);
    boxes.emplace_back(lo, hi);
  }
  std::vector<ScreenBox> screen;
  for (const auto& [lo, hi] : boxes) {
    // Pad by a relative epsilon so that rounding never culls a ray that grazes the box.
    const Vec3 pad = 1e-6 * (glm::abs(hi - lo) + glm::abs(lo) + glm::abs(hi)) + 1e-12;
    ScreenBox b;
    if (!project_box(p.camera, lo - pad, hi + pad, &b)) return culled;  // reaches behind us
    screen.push_back(b);
  }
  for (std::size_t i = 0; i < p.tiles.size(); ++i) {
    const Tile& t = p.tiles[i];
    bool overlaps = false;
    for (const ScreenBox& b : screen) {
      // One pixel of margin on top of the projected bounds.
      if (b.x1 + 1.0 >= t.x0 && b.x0 - 1.0 <= t.x1 && b.y1 + 1.0 >= t.y0 && b.y0 - 1.0 <= t.y1) {
        overlaps = true;
        break;
      }
    }
    culled[i] = overlaps ? 0 : 1;
  }
  return culled;
}

}  // namespace tessera
