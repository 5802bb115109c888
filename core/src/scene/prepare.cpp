#include <tessera/render.h>

#include <tessera/cuda_render.h>

#include <tessera/loop_bounds.h>
#include <tessera/number_text.h>

#include "kernels/workers.h"
#include "mesh/mesh_summary.h"
#include "scene/adaptive_preview.h"
#include "scene/amr_tables.h"
#include "scene/axis_tables.h"
#include "scene/prepared_scene_impl.h"
#include "scene/tile_culling.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace tessera {
namespace {

void require(bool ok, const std::string& msg) {
  if (!ok) throw std::invalid_argument(msg);
}

std::string vec(const Vec3& v) {
  std::string out = "[";
  out += short_number(v.x);
  out += ", ";
  out += short_number(v.y);
  out += ", ";
  out += short_number(v.z);
  out += "]";
  return out;
}

double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// One light's checks as its kind's LightKind::validate calls them, naming the light.
template <class Point, class Length, class Radiance>
struct LightCheck {
  const std::string& name;
  const Point& point_fn;
  const Length& length_fn;
  const Radiance& radiance_fn;
  void point(const char* key, const Vec3& p) const { point_fn(name, key, p); }
  void length(const char* key, double v) const { length_fn(name, key, v); }
  void radiance(const Color& L) const { radiance_fn(name, L); }
};

/// Every light's checks, kind by kind in LightDesc's order (the light set's order), each
/// named "<kind> <i>" with i counted per kind in list order.
template <std::size_t... I, class... Fn>
void validate_lights(const std::vector<LightDesc>& lights, std::index_sequence<I...>, const Fn&... fn) {
  const auto one_kind = [&](auto index) {
    using Desc = std::variant_alternative_t<decltype(index)::value, LightDesc>;
    using Kind = LightKind<Desc>;
    std::size_t i = 0;
    for (const LightDesc& l : lights)
      if (const Desc* d = std::get_if<Desc>(&l)) {
        const std::string name = std::string(Kind::kName) + " " + std::to_string(i++);
        Kind::validate(*d, LightCheck<Fn...>{name, fn...});
      }
  };
  (one_kind(std::integral_constant<std::size_t, I>{}), ...);
}

/// Positions, lengths and steps against the data (loop_bounds.h): what would make a sampling
/// loop stall or run unboundedly, or lose every digit of precision, is refused here, naming
/// the key and its value.
void validate_scale(const FieldView& field, const SceneDesc& s) {
  const VolumeGeometry& g = s.geometry;
  const Bounds b = field_bounds(field, g);
  const std::string dims =
      std::to_string(field.dims[0]) + "x" + std::to_string(field.dims[1]) + "x" + std::to_string(field.dims[2]);
  require(is_finite(b.hi) && is_finite(b.hi - b.lo) && std::isfinite(glm::length(b.hi - b.lo)),
          "volume spacing " + vec(g.spacing) + " with origin " + vec(g.origin) + " and dims " + dims +
              " makes the data bounds overflow (their corner or diagonal is not finite)");
  const bool rectilinear = g.coords[0] || g.coords[1] || g.coords[2];
  if (!rectilinear) {
    require(std::min({g.spacing.x, g.spacing.y, g.spacing.z}) >= kMinSpacing &&
                std::max({g.spacing.x, g.spacing.y, g.spacing.z}) <= kMaxSpacing,
            "volume spacing " + vec(g.spacing) + " is outside [1e-100, 1e100] on some axis");
  } else {
    for (int a = 0; a < 3; ++a) {
      const double lo = smallest_spacing(field, g, a), hi = largest_spacing(field, g, a);
      require(!(lo < kMinSpacing) && !(hi > kMaxSpacing),
              std::string(g.coords[a] ? "rectilinear axis " : "volume spacing along ") + axis_name(a) +
                  ": spacings from " + short_number(lo) + " to " + short_number(hi) + " are outside [1e-100, 1e100]");
    }
  }
  // The smallest spacing of every axis, a rectilinear axis' smallest interval included
  const double h = smallest_spacing(field, g);
  const double lim = kMaxCoordinateVoxels * h;
  const std::string why =
      " beyond 2^40 smallest spacings (" + short_number(lim) + ") from 0, where a double no longer resolves a voxel";
  const auto near = [&](const Vec3& p) { return max_abs(p) <= lim; };
  if (!rectilinear)
    require(near(g.origin) && near(b.hi),
            "volume origin " + vec(g.origin) + " puts the data (far corner " + vec(b.hi) + ")" + why);
  else require(near(b.lo) && near(b.hi), "the data's box from " + vec(b.lo) + " to " + vec(b.hi) + " lies" + why);
  // Camera
  const CameraDesc& c = s.camera;
  require(is_finite(c.position), "camera.position " + vec(c.position) + " is not finite");
  require(is_finite(c.look_at), "camera.look_at " + vec(c.look_at) + " is not finite");
  require(near(c.position), "camera.position " + vec(c.position) + " lies" + why);
  require(near(c.look_at), "camera.look_at " + vec(c.look_at) + " lies" + why);
  require(!(c.aperture > lim), "camera.aperture " + short_number(c.aperture) +
                                   " is larger than 2^40 smallest spacings (" + short_number(lim) + ")");
  require(!(c.focus_distance > lim), "camera.focus_distance " + short_number(c.focus_distance) +
                                         " is larger than 2^40 smallest spacings (" + short_number(lim) + ")");
  // Lights
  const auto light_point = [&](const std::string& name, const char* key, const Vec3& p) {
    require(is_finite(p), name + ": " + key + " " + vec(p) + " is not finite");
    require(near(p), name + ": " + key + " " + vec(p) + " lies" + why);
  };
  const auto light_length = [&](const std::string& name, const char* key, double v) {
    require(!(v > lim), name + ": " + key + " " + short_number(v) + " is larger than 2^40 smallest spacings (" +
                            short_number(lim) + ")");
  };
  const auto radiance = [&](const std::string& name, const Color& L) {
    require(is_finite(L) && std::min({L.x, L.y, L.z}) >= 0.0 && max_abs(L) <= kMaxRadiance,
            name + ": radiance (color * intensity) " + vec(L) + " must be finite, >= 0 and at most 1e30");
  };
  const BackgroundDesc& bg = s.background;
  if (bg.type != BackgroundType::EnvMap) {
    const double top = std::max({max_abs(bg.color), max_abs(bg.top), max_abs(bg.middle), max_abs(bg.bottom)});
    const double peak = bg.type == BackgroundType::Constant ? max_abs(bg.color) : top;
    require(std::isfinite(bg.intensity) && !(peak * bg.intensity > kMaxRadiance),
            "background.intensity " + short_number(bg.intensity) + " times its color makes a radiance above 1e30");
  }
  validate_lights(s.lights, std::make_index_sequence<std::variant_size_v<LightDesc>>{}, light_point, light_length,
                  radiance);
  // Raymarch: at most kMaxMarchSteps steps across the box diagonal
  if (s.integrator.free_path == FreePath::Raymarch) {
    const double diag = glm::length(b.hi - b.lo) / h;  // in smallest spacings
    const double min_step = diag / kMaxMarchSteps;
    require(s.integrator.step >= min_step,
            "integrator.step " + short_number(s.integrator.step) + " is below the minimum " + short_number(min_step) +
                " for this volume (dims " + dims + "): at most 2^20 raymarch steps across the data");
  }
}

/// The scene's checks against the field's geometry (dims, dtype); reads no value.
void validate_scene(const FieldView& field, const SceneDesc& s) {
  const VolumeGeometry& g = s.geometry;
  // Origin and spacing place the uniform axes only (a rectilinear axis has its coordinates)
  require(g.association == Association::Vertex || g.association == Association::Cell,
          "volume association " + std::to_string(static_cast<int>(g.association)) + " is neither vertex nor cell");
  for (int a = 0; a < 3; ++a) {
    if (g.coords[a]) continue;
    require(std::isfinite(g.origin[a]), "volume origin " + vec(g.origin) + " must be finite");
    require(std::isfinite(g.spacing[a]) && g.spacing[a] > 0,
            "volume spacing " + vec(g.spacing) + " must be finite and > 0 on every axis");
  }
  validate_axes(field, g);
  const TransferFunction& tf = s.tf;
  // hi - lo must be finite too: u = (v - lo) / (hi - lo) is NaN for v near hi otherwise.
  require(std::isfinite(tf.lo) && std::isfinite(tf.hi) && tf.lo < tf.hi && std::isfinite(tf.hi - tf.lo),
          "transfer function range [" + short_number(tf.lo) + ", " + short_number(tf.hi) +
              "] must be finite with lo < hi and a finite width hi - lo");
  require(std::isfinite(tf.density_scale) && tf.density_scale >= 0.0, "density_scale must be finite and >= 0");
  for (int i = 0; i < tf.opacity.size(); ++i)
    require(tf.opacity.v(i) >= 0.0 && std::isfinite(tf.opacity.v(i)),
            "opacity value " + short_number(tf.opacity.v(i)) + " must be finite and >= 0");
  const ImageDesc& im = s.image;
  require(im.width >= 1 && im.height >= 1, "image size must be at least 1x1");
  require(im.spp >= 1, "spp must be >= 1");
  const IntegratorDesc& in = s.integrator;
  require(in.max_bounces >= 1, "max_bounces must be >= 1");
  require(in.rr_depth >= 1, "rr_depth must be >= 1");
  require(in.phase_g > -1.0 && in.phase_g < 1.0, "phase_g must be in (-1, 1)");
  require(in.gradient_factor >= 0.0 && std::isfinite(in.gradient_factor), "gradient_factor must be >= 0");
  require(in.step > 0.0 && std::isfinite(in.step),
          "integrator.step " + short_number(in.step) + " must be finite and > 0");
  require(in.macrocell >= 1, "macrocell edge must be >= 1");
  require(s.lights.size() <= static_cast<std::size_t>(kMaxLights),
          "at most " + std::to_string(kMaxLights) + " area lights");
  require(s.options.tile >= 0, "tile edge must be >= 0");
  require(s.options.threads >= 0, "threads must be >= 0");
  validate_scale(field, s);
}

void validate(const FieldView& field, const SceneDesc& s) {
  field.validate("field");
  validate_scene(field, s);
}

/// The field descriptor of a paged field: global dims and dtype, dense strides, no data.
FieldView global_descriptor(const PagedField& f) {
  FieldView v;
  v.dtype = f.dtype;
  const auto size = static_cast<std::int64_t>(dtype_size(f.dtype));
  for (int a = 0; a < 3; ++a) v.dims[a] = f.dims[a];
  v.byte_strides[0] = size;
  v.byte_strides[1] = size * f.dims[0];
  v.byte_strides[2] = size * f.dims[0] * f.dims[1];
  return v;
}

std::string dims_text(const std::int64_t d[3]) {
  return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
}

/// A summary handed to prepare fits the field: its macrocell edge is the scene's `edge` and
/// its cells cover `dims` (`what` names the field in the message).
void require_summary_fits(const FieldSummary& summary, int edge, const std::int64_t dims[3], const char* what) {
  require(summary.edge() == edge, std::string(what) + ": the field summary has macrocell edge " +
                                      std::to_string(summary.edge()) + ", this scene needs " + std::to_string(edge) +
                                      " for dims " + dims_text(dims));
  for (int a = 0; a < 3; ++a)
    require(summary.cells()[a] == std::max<std::int64_t>(1, (dims[a] - 1 + edge - 1) / edge),
            std::string(what) + ": the field summary's " + dims_text(summary.cells()) + " cells do not fit dims " +
                dims_text(dims) + " with edge " + std::to_string(edge));
}

/// A paged field's own checks: the cache's grid, the own block inside the global dims.
void validate_paged(const PagedField& f) {
  for (int a = 0; a < 3; ++a)
    require(f.dims[a] >= 1, "paged field: global dims " + dims_text(f.dims) + " must be >= 1 on every axis");
  require(f.cache != nullptr, "paged field: no brick cache");
  const BrickGrid& g = f.cache->grid();
  require(g.dtype == f.dtype && g.dims[0] == f.dims[0] && g.dims[1] == f.dims[1] && g.dims[2] == f.dims[2],
          "paged field: the brick cache is for a " + std::string(dtype_name(g.dtype)) + " field of " +
              dims_text(g.dims) + ", the field is " + dtype_name(f.dtype) + " " + dims_text(f.dims));
  require(!f.local_device_only || (f.local_device != nullptr && f.local.data == f.local_device),
          "paged field: an own block in device memory only needs local.data == local_device");
  if (f.local.data == nullptr) return;  // no own block: every vertex through the cache
  f.local.validate("paged field: own block");
  require(f.local.dtype == f.dtype,
          "paged field: own block is " + std::string(dtype_name(f.local.dtype)) + ", the field " + dtype_name(f.dtype));
  for (int a = 0; a < 3; ++a)
    require(f.offset[a] >= 0 && f.offset[a] + f.local.dims[a] <= f.dims[a],
            "paged field: own block of " + dims_text(f.local.dims) + " at offset " + dims_text(f.offset) +
                " is not inside the global dims " + dims_text(f.dims));
}

}  // namespace

double Bounds::radius() const { return 0.5 * glm::length(hi - lo); }

Bounds field_bounds(const FieldView& field, const VolumeGeometry& g) {
  const bool cell = g.association == Association::Cell;
  Bounds b;
  for (int a = 0; a < 3; ++a) {
    const double* c = g.coords[a];
    // Vertex data: the vertices' box; cell data: the cells' box (one more boundary than cells)
    const std::int64_t last = field.dims[a] - (cell ? 0 : 1);
    if (c) {
      b.lo[a] = c[0];
      b.hi[a] = c[last];
    } else {
      b.lo[a] = g.origin[a];
      b.hi[a] = g.origin[a] + static_cast<double>(last) * g.spacing[a];
    }
  }
  return b;
}

std::optional<std::pair<double, double>> field_range(const FieldView& field) {
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
  if (lo > hi) return std::nullopt;
  return std::pair{lo, hi};
}

PreparedScene::PreparedScene() : m_impl(std::make_unique<PreparedSceneImpl>()) {}
PreparedScene::~PreparedScene() = default;
PreparedScene::PreparedScene(PreparedScene&&) noexcept = default;
PreparedScene& PreparedScene::operator=(PreparedScene&&) noexcept = default;
const PreparedSceneImpl& prepared_scene_impl(const PreparedScene& scene) { return *scene.m_impl; }
const SceneDesc& PreparedScene::desc() const { return m_impl->desc; }
const std::vector<Tile>& PreparedScene::tiles() const { return m_impl->tiles; }
Bounds PreparedScene::bounds() const { return m_impl->bounds; }

const std::shared_ptr<const FieldSummary>& PreparedScene::summary() const { return m_impl->grid.summary(); }
bool PreparedScene::summary_reused() const { return m_impl->summary_reused; }
const std::shared_ptr<const MeshLayout>& PreparedScene::mesh_layout() const { return m_impl->mesh.layout(); }
bool PreparedScene::mesh_layout_reused() const { return m_impl->mesh.layout_reused(); }

PreparedScene prepare(const FieldView& field, const SceneDesc& scene) { return prepare(field, scene, nullptr); }

namespace {

/// Everything prepare() derives once the field descriptor, its summary and (paged mode) the
/// paged view are settled; the scene is validated.
void prepare_from(PreparedSceneImpl& p, const FieldView& field, const SceneDesc& scene,
                  std::shared_ptr<const FieldSummary> summary, const PagedFieldView* paged,
                  const AmrField* amr = nullptr, const MagnitudeField* magnitude = nullptr) {
  p.desc = scene;
  p.field = field;
  const VolumeGeometry& g = scene.geometry;
  p.bounds = field_bounds(field, g);
  p.camera = Camera(scene.camera, scene.image.width, scene.image.height);
  const double h_min = smallest_spacing(field, g);  // a rectilinear axis' smallest interval included
  p.march_step = scene.integrator.step * h_min;
  p.grid.set_summary(std::move(summary));
  // The medium's p space (grid_medium.h): sample i at p = i on a uniform axis (a cell's
  // centre half a spacing in from its low corner), p = x on a rectilinear one
  p.origin = g.origin;
  p.inv_spacing = 1.0 / g.spacing;
  const bool cell = g.association == Association::Cell;
  for (int a = 0; a < 3; ++a) {
    const double hi_index = static_cast<double>(field.dims[a] - 1);
    if (g.coords[a]) {
      p.origin[a] = 0.0;
      p.inv_spacing[a] = 1.0;
      p.box_lo[a] = p.bounds.lo[a];
      p.box_hi[a] = p.bounds.hi[a];
    } else if (cell) {
      p.origin[a] = g.origin[a] + 0.5 * g.spacing[a];
      p.box_lo[a] = -0.5;
      p.box_hi[a] = hi_index + 0.5;
    } else {
      p.box_lo[a] = 0.0;
      p.box_hi[a] = hi_index;
    }
  }
  p.axes.build(field, g, p.grid.edge(), p.grid.cells());
  // Extinction clamp: beyond kMaxOpticalThicknessPerVoxel per smallest spacing the medium is
  // opaque at sub-voxel scale in double precision (loop_bounds.h)
  p.sigma_max = kMaxOpticalThicknessPerVoxel / h_min;
  p.grid.update(scene.tf, p.sigma_max);
  if (amr) p.amr.build(*amr, g.association, p.grid.edge(), p.grid.cells(), paged);
  p.env = Environment(scene.background);
  p.lights = make_lights(scene, &p.env);
  p.has_emission = !scene.tf.emission.is_zero();
  p.has_specular = !scene.tf.specular.is_zero();
  p.tiles = make_tiles(scene.image.width, scene.image.height, scene.options.tile, scene.options.order);
  p.tile_culled = cull_tiles(p);
  p.kernel = make_kernel_scene(p);
  if (paged) p.kernel.paged = *paged;
  if (amr) p.kernel.amr = p.amr.view();
  if (magnitude) p.kernel.magnitude = MagnitudeFieldView::of(*magnitude);
  // The preview renders with the above: on the host here, or on the device by every GPU render
  p.preview_on_device = scene.options.device == Device::Cuda && scene.image.target_error > 0.0;
  if (!p.preview_on_device) p.kernel.adaptive_scale = adaptive_preview_scale(p.kernel, scene.options);
}

}  // namespace

PreparedScene prepare(const FieldView& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> reuse) {
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    validate(field, scene);
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    // Majorants: one global cell, or macrocells of `macrocell` voxels; the field pass only
    // when no matching summary is given
    const int edge = majorant_edge(field, scene.integrator);
    p.summary_reused = reuse && reuse->matches(field, edge);
    prepare_from(p, field, scene, p.summary_reused ? std::move(reuse) : FieldSummary::build(field, edge), nullptr);
    return ps;
  });
}

PreparedScene prepare(const MagnitudeField& field, const SceneDesc& scene,
                      std::shared_ptr<const FieldSummary> summary) {
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    field.validate();
    // The scene is checked against component 0: dims and placement are the field's
    const FieldView& first = field.components[0];
    validate_scene(first, scene);
    const int edge = majorant_edge(first, scene.integrator);
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    if (summary) {
      require_summary_fits(*summary, edge, first.dims, "vector field");
      p.summary_reused = true;
    } else {
      summary = magnitude_summary(field, edge);
    }
    prepare_from(p, first, scene, std::move(summary), nullptr, nullptr, &field);
    return ps;
  });
}

PreparedScene prepare(const PagedField& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> summary) {
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    validate_paged(field);
    const FieldView global = global_descriptor(field);
    validate_scene(global, scene);
    const int edge = majorant_edge(global, scene.integrator);
    require(summary != nullptr, "paged field: no field summary (the combined partial summaries of every block)");
    require_summary_fits(*summary, edge, field.dims, "paged field");
    // The host's view: the own block read in place, unless it is device memory only (then
    // its vertices come through the cache like the others)
    const bool own_on_host = field.local.data != nullptr && !field.local_device_only;
    PagedFieldView view;
    view.dtype = field.dtype;
    view.local = field.local;
    if (!own_on_host) {
      view.local = FieldView{};
      view.local.dtype = field.dtype;
    }
    const BrickGrid& g = field.cache->grid();
    view.shift = g.shift;
    for (int a = 0; a < 3; ++a) {
      view.dims[a] = field.dims[a];
      view.bricks[a] = g.bricks[a];
      view.lo[a] = own_on_host ? field.offset[a] : 0;
      view.hi[a] = own_on_host ? field.offset[a] + field.local.dims[a] : 0;
    }
    view.cache = field.cache;
    view.in_place = field.cache->in_place();  // the rank's other own blocks (BrickCache::set_in_place)
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    p.summary_reused = true;  // never a pass over the values here
    p.paged_local_device = field.local.data ? field.local_device : nullptr;
    if (field.local.data && field.local_device_only) {
      p.paged_device_own = field.local;
      for (int a = 0; a < 3; ++a) p.paged_device_lo[a] = field.offset[a];
    }
    prepare_from(p, global, scene, std::move(summary), &view);
    return ps;
  });
}

PreparedScene prepare(const AmrField& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> summary) {
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    const VolumeGeometry& g = scene.geometry;
    for (int a = 0; a < 3; ++a)
      require(g.coords[a] == nullptr, std::string("refinement levels with a rectilinear axis (") + axis_name(a) +
                                          ") are not supported yet: give uniform axes");
    require(g.association == Association::Vertex || g.association == Association::Cell,
            "volume association " + std::to_string(static_cast<int>(g.association)) + " is neither vertex nor cell");
    check_amr(field, g.association);
    // Level 0's descriptor: dims and dtype, no data (the values are the patches')
    PagedField level0;
    level0.dtype = field.dtype;
    for (int a = 0; a < 3; ++a) level0.dims[a] = field.dims[a];
    const FieldView global = global_descriptor(level0);
    validate_scene(global, scene);
    const int edge = majorant_edge(global, scene.integrator);
    // Distributed mode: other ranks' patches through the cache over the virtual grid
    PagedFieldView view;
    if (field.cache) {
      const BrickGrid& bg = field.cache->grid();
      require(bg.dtype == field.dtype && bg.dims[0] == field.layout.dims[0] && bg.dims[1] == field.layout.dims[1] &&
                  bg.dims[2] == field.layout.dims[2],
              "refinement levels: the brick cache is for a " + std::string(dtype_name(bg.dtype)) + " grid of " +
                  dims_text(bg.dims) + ", the levels' virtual grid is " + dtype_name(field.dtype) + " " +
                  dims_text(field.layout.dims));
      require(summary != nullptr, "refinement levels in distributed mode: no field summary (the combined parts of "
                                  "every rank's patches, amr_summary_parts)");
      view.dtype = field.dtype;
      view.shift = bg.shift;
      for (int a = 0; a < 3; ++a) {
        view.dims[a] = bg.dims[a];
        view.bricks[a] = bg.bricks[a];
      }
      view.cache = field.cache;
    }
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    if (summary) {
      require_summary_fits(*summary, edge, field.dims, "refinement levels");
      p.summary_reused = true;
    } else {
      summary = amr_summary(field, g.association, edge);
    }
    prepare_from(p, global, scene, std::move(summary), field.cache ? &view : nullptr, &field);
    return ps;
  });
}

namespace {

/// The scene over the grid laid over the mesh's box (mesh/mesh_tables.h), p.mesh built;
/// `summary` gives the macrocells' FieldSummary for the scene's edge.
template <class Summary>
void prepare_mesh_scene(PreparedSceneImpl& p, const SceneDesc& scene, Summary&& summary) {
  SceneDesc s = scene;
  s.geometry = p.mesh.geometry();
  PagedField grid;
  grid.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) grid.dims[a] = p.mesh.dims()[a];
  const FieldView global = global_descriptor(grid);
  validate_scene(global, s);
  const int edge = majorant_edge(global, s.integrator);
  prepare_from(p, global, s, summary(edge), nullptr);
}

/// A mesh whose arrays are GPU memory (Mesh::device): checked (unless `checked` covers it)
/// and summarised on the device (cuda/mesh_device.h) over the layout of an earlier prepare.
void prepare_device_mesh(PreparedSceneImpl& p, const Mesh& mesh, const SceneDesc& scene,
                         std::shared_ptr<const MeshLayout> reuse, const MeshChecked& checked) {
  require(scene.options.device == Device::Cuda,
          "a mesh in device memory (Mesh::device) renders on the GPU only: options.device must be cuda");
  require(reuse && reuse->fits(mesh), "a mesh in device memory (Mesh::device) needs the layout of an earlier prepare "
                                      "of the same geometry (reuse): the layout is built on the host");
  void* stream = scene.options.cuda_stream;
  // The ghost masks the layout was built over (a promise broken there would have the kernels
  // read ghosts' cells, whose indices nothing checks): their sums on the device ({0, 0}
  // without masks, as the layout recorded: fits() requires the masks where they were)
  const MeshGeometryHash g = cuda_mesh_ghost_sums(mesh, stream);
  require(g.a == reuse->ghost_sums().a && g.b == reuse->ghost_sums().b,
          "mesh: the ghost fields are not those the layout was built over (a cell of it is a ghost now, or a ghost "
          "real): the geometry is not the one promised unchanged");
  const MeshChecked receipt = checked.covers(mesh, false) ? checked : cuda_check_mesh_indices(mesh, stream);
  p.mesh.build_on_device(mesh, std::move(reuse));
  prepare_mesh_scene(p, scene, [&](int edge) {
    return cuda_mesh_summary(mesh, p.mesh.geometry(), p.mesh.dims(), edge, stream, &receipt);
  });
}

}  // namespace

PreparedScene prepare(const Mesh& mesh, const SceneDesc& scene, std::shared_ptr<const MeshLayout> reuse,
                      const MeshChecked& checked) {
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    if (mesh.device) {
      prepare_device_mesh(p, mesh, scene, std::move(reuse), checked);
      return ps;
    }
    const bool fits = reuse && reuse->fits(mesh);
    if (!checked.covers(mesh, !fits)) {  // a reused layout: the indices; a new one: the shapes too
      if (fits) check_mesh_indices(mesh);
      else check_mesh(mesh);
    }
    p.mesh.build(mesh, fits ? std::move(reuse) : nullptr);
    prepare_mesh_scene(p, scene, [&](int edge) { return mesh_summary(p.mesh, edge); });
    return ps;
  });
}

namespace {

/// The macrocell edge prepare_mesh_scene takes for `scene` over the grid of `layout`.
int mesh_edge(const MeshLayout& layout, const SceneDesc& scene) {
  FieldView grid;
  grid.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) grid.dims[a] = layout.dims()[a];
  return majorant_edge(grid, scene.integrator);
}

/// The tables a share of a host mesh's summary is taken over: `layout` fitting `mesh`, whose
/// indices `checked` covers (else check_mesh_indices); the scene's macrocell edge in *edge.
MeshTables shared_tables(const Mesh& mesh, const SceneDesc& scene, const std::shared_ptr<const MeshLayout>& layout,
                         const MeshChecked& checked, int* edge) {
  require(!mesh.device, "a mesh summary's share: the mesh must be host memory (not Mesh::device)");
  require(layout && layout->fits(mesh), "a mesh summary's share needs the layout of an earlier prepare of the same "
                                        "geometry (mesh_layout_fits)");
  if (!checked.covers(mesh, false)) check_mesh_indices(mesh);
  MeshTables t;
  t.build(mesh, layout);
  *edge = mesh_edge(*layout, scene);
  return t;
}

}  // namespace

FieldSummary::Parts mesh_summary_parts(const Mesh& mesh, const SceneDesc& scene,
                                       const std::shared_ptr<const MeshLayout>& layout, const MeshChecked& checked,
                                       int share, int shares) {
  return within_render_threads(scene.options, [&] {
    int edge = 1;
    const MeshTables t = shared_tables(mesh, scene, layout, checked, &edge);
    return mesh_summary_share(t, edge, share, shares);
  });
}

std::uint64_t mesh_summary_cells(const MeshLayout& layout, const SceneDesc& scene) {
  const MacroGrid m = macro_grid(layout.geometry(), layout.dims(), mesh_edge(layout, scene));
  return static_cast<std::uint64_t>(m.cells[0] * m.cells[1] * m.cells[2]);
}

std::shared_ptr<const FieldSummary> mesh_summary_of_parts(FieldSummary::Parts&& parts, const Mesh& mesh,
                                                          const SceneDesc& scene,
                                                          const std::shared_ptr<const MeshLayout>& layout) {
  require(layout && layout->fits(mesh), "a mesh summary's parts need the layout they were taken over");
  return mesh_summary_of(std::move(parts), *layout, mesh_edge(*layout, scene));
}

PreparedScene prepare(const Mesh& mesh, const SceneDesc& scene, std::shared_ptr<const MeshLayout> reuse,
                      const MeshChecked& checked, std::shared_ptr<const FieldSummary> summary) {
  require(summary != nullptr, "mesh: a null summary (prepare without one summarises the values itself)");
  require(!mesh.device, "mesh: a summary made of shares is for host memory (not Mesh::device)");
  require(reuse && reuse->fits(mesh), "mesh: a summary made of shares needs the layout it was taken over (reuse "
                                      "must fit the mesh)");
  return within_render_threads(scene.options, [&]() -> PreparedScene {
    PreparedScene ps;
    PreparedSceneImpl& p = *ps.m_impl;
    if (!checked.covers(mesh, false)) check_mesh_indices(mesh);
    p.mesh.build(mesh, std::move(reuse));
    prepare_mesh_scene(p, scene, [&](int edge) {
      require_summary_fits(*summary, edge, p.mesh.dims(), "mesh");
      return summary;
    });
    return ps;
  });
}

}  // namespace tessera
