#include <tessera/render.h>

#include "adaptive_sampling.h"
#include "prepared_scene_impl.h"
#include "tile_culling.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace tessera {
namespace {

void require(bool ok, const std::string& msg) {
  if (!ok) throw std::invalid_argument(msg);
}

bool finite3(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void validate(const FieldView& field, const SceneDesc& s) {
  field.validate("field");
  const VolumeGeometry& g = s.geometry;
  require(finite3(g.origin), "volume origin must be finite");
  require(finite3(g.spacing) && g.spacing.x > 0 && g.spacing.y > 0 && g.spacing.z > 0,
          "volume spacing must be finite and > 0 on every axis");
  const TransferFunction& tf = s.tf;
  // hi - lo must be finite too: u = (v - lo) / (hi - lo) is NaN for v near hi otherwise.
  require(std::isfinite(tf.lo) && std::isfinite(tf.hi) && tf.lo < tf.hi && std::isfinite(tf.hi - tf.lo),
          "transfer function range [" + std::to_string(tf.lo) + ", " + std::to_string(tf.hi) +
              "] must be finite with lo < hi and a finite width hi - lo");
  require(std::isfinite(tf.density_scale) && tf.density_scale >= 0.0,
          "density_scale must be finite and >= 0");
  for (int i = 0; i < tf.opacity.size(); ++i)
    require(tf.opacity.v(i) >= 0.0, "opacity values must be >= 0");
  const ImageDesc& im = s.image;
  require(im.width >= 1 && im.height >= 1, "image size must be at least 1x1");
  require(im.spp >= 1, "spp must be >= 1");
  const IntegratorDesc& in = s.integrator;
  require(in.max_bounces >= 1, "max_bounces must be >= 1");
  require(in.rr_depth >= 1, "rr_depth must be >= 1");
  require(in.phase_g > -1.0 && in.phase_g < 1.0, "phase_g must be in (-1, 1)");
  require(in.gradient_factor >= 0.0 && std::isfinite(in.gradient_factor), "gradient_factor must be >= 0");
  require(in.step > 0.0 && std::isfinite(in.step), "raymarch step must be > 0");
  require(in.macrocell >= 1, "macrocell edge must be >= 1");
  require(s.rect_lights.size() + s.sphere_lights.size() <= static_cast<std::size_t>(kMaxLights),
          "at most " + std::to_string(kMaxLights) + " area lights");
  for (const auto& l : s.rect_lights)
    require(finite3(l.position) && finite3(l.target) && finite3(l.radiance) &&
                std::min({l.radiance.x, l.radiance.y, l.radiance.z}) >= 0.0,
            "rect light: position, target and radiance must be finite, radiance >= 0");
  for (const auto& l : s.sphere_lights)
    require(finite3(l.center) && finite3(l.radiance) &&
                std::min({l.radiance.x, l.radiance.y, l.radiance.z}) >= 0.0,
            "sphere light: position and radiance must be finite, radiance >= 0");
  require(s.options.tile >= 0, "tile edge must be >= 0");
  require(s.options.threads >= 0, "threads must be >= 0");
}

}  // namespace

double Bounds::radius() const { return 0.5 * glm::length(hi - lo); }

Bounds field_bounds(const FieldView& field, const VolumeGeometry& g) {
  const Vec3 n(static_cast<double>(field.dims[0] - 1), static_cast<double>(field.dims[1] - 1),
               static_cast<double>(field.dims[2] - 1));
  return Bounds{g.origin, g.origin + n * g.spacing};
}

std::pair<double, double> field_range(const FieldView& field) {
  field.validate("field");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  dispatch_dtype(field, [&](auto view) {
    for (std::int64_t k = 0; k < field.dims[2]; ++k)
      for (std::int64_t j = 0; j < field.dims[1]; ++j)
        for (std::int64_t i = 0; i < field.dims[0]; ++i) {
          const double v = view.load(i, j, k);
          if (std::isfinite(v)) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
          }
        }
  });
  if (lo > hi) return {0.0, 0.0};
  return {lo, hi};
}

PreparedScene::PreparedScene() : m_impl(std::make_unique<PreparedSceneImpl>()) {}
PreparedScene::~PreparedScene() = default;
PreparedScene::PreparedScene(PreparedScene&&) noexcept = default;
PreparedScene& PreparedScene::operator=(PreparedScene&&) noexcept = default;
const SceneDesc& PreparedScene::desc() const { return m_impl->desc; }
const std::vector<Tile>& PreparedScene::tiles() const { return m_impl->tiles; }
Bounds PreparedScene::bounds() const { return m_impl->bounds; }

const std::shared_ptr<const FieldSummary>& PreparedScene::summary() const { return m_impl->grid.summary(); }
bool PreparedScene::summary_reused() const { return m_impl->summary_reused; }

PreparedScene prepare(const FieldView& field, const SceneDesc& scene) { return prepare(field, scene, nullptr); }

PreparedScene prepare(const FieldView& field, const SceneDesc& scene,
                      std::shared_ptr<const FieldSummary> reuse) {
  validate(field, scene);
  PreparedScene ps;
  PreparedSceneImpl& p = *ps.m_impl;
  p.desc = scene;
  p.field = field;
  p.bounds = field_bounds(field, scene.geometry);
  p.camera = Camera(scene.camera, scene.image.width, scene.image.height);
  p.inv_spacing = 1.0 / scene.geometry.spacing;
  p.march_step = scene.integrator.step *
                 std::min({scene.geometry.spacing.x, scene.geometry.spacing.y, scene.geometry.spacing.z});
  // Majorants: one global cell, or macrocells of `macrocell` voxels; the field pass only
  // when no matching summary is given
  const int edge = majorant_edge(field, scene.integrator);
  p.summary_reused = reuse && reuse->matches(field, edge);
  p.grid.set_summary(p.summary_reused ? std::move(reuse) : FieldSummary::build(field, edge));
  p.grid.update(scene.tf);
  p.env = Environment(scene.background);
  for (const auto& l : scene.rect_lights) p.rects.emplace_back(l);
  for (const auto& l : scene.sphere_lights) p.spheres.emplace_back(l);
  p.light_count = static_cast<int>(p.rects.size() + p.spheres.size()) + (p.env.emits() ? 1 : 0);
  p.has_emission = !scene.tf.emission.is_zero();
  p.has_specular = !scene.tf.specular.is_zero();
  p.tiles = make_tiles(scene.image.width, scene.image.height, scene.options.tile, scene.options.order);
  p.tile_culled = cull_tiles(p);
  p.adaptive_scale = adaptive_preview_scale(p);  // needs everything above
  return ps;
}

}  // namespace tessera
