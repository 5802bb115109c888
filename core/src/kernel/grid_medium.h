#pragma once
/// GridMedium<T>: the heterogeneous medium seen by the kernels. Works in volume-local
/// coordinates p = (x - origin) / spacing per axis (the KernelScene's origin and inv_spacing):
/// on a uniform axis sample i (a vertex, or a cell centre for cell data) sits at p = i
/// whatever the world placement; on a rectilinear axis p is the world coordinate itself and
/// the axis' AxisMap finds the segment. World distances t stay the ray parameter.
///
/// Cell data fills the cells' whole box: the box [box_lo, box_hi] reaches half a cell beyond
/// the outermost centres, where the value is clamped to the nearest centre, and the outermost
/// macrocells reach over that half cell (outer_half).
#include <tessera/brick_cache.h>
#include <tessera/field_view.h>
#include <tessera/transfer_function.h>

#include "field/majorant_grid.h"
#include "kernel/amr_view.h"
#include "kernel/axis_map.h"
#include "kernel/magnitude_view.h"
#include "kernel/trilinear.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace tessera {

/// The kernels' Value for a demand-paged field (brick_cache.h): the dtype is read per load.
struct PagedValue {};

/// The kernels' Value for a field with some rectilinear axis: T's loads (a dtype's C++ type
/// or PagedValue) with the AxisMap lookups compiled in. Uniform fields use T itself, whose
/// kernels hold none of that code (their arithmetic and inlining are those of uniform data).
template <class T>
struct Rectilinear {};

/// The kernels' Value for a hierarchy of refinement levels (amr.h): every value comes from
/// AmrFieldView::value (the dtype is read per load, as for PagedValue).
struct AmrValue {};

/// The kernels' Value for the magnitude of a vector's three components (magnitude_field.h):
/// every value comes from MagnitudeFieldView::load (each component's dtype read per load).
struct MagnitudeValue {};

/// A Value's load type and whether it carries rectilinear axes or refinement levels.
template <class V>
struct ValueTraits {
  using base = V;
  static constexpr bool kRectilinear = false;
  static constexpr bool kAmr = std::is_same_v<V, AmrValue>;
};
template <class T>
struct ValueTraits<Rectilinear<T>> {
  using base = T;
  static constexpr bool kRectilinear = true;
  static constexpr bool kAmr = false;
};

/// How a GridMedium<T> reads vertices: in place for a real dtype, through the brick cache
/// for PagedValue.
template <class T>
struct FieldAccessor {
  using type = TypedFieldView<T>;
};
template <>
struct FieldAccessor<PagedValue> {
  using type = PagedFieldView;
};
template <>
struct FieldAccessor<AmrValue> {
  using type = AmrFieldView;
};
template <>
struct FieldAccessor<MagnitudeValue> {
  using type = MagnitudeFieldView;
};
template <class T>
struct FieldAccessor<Rectilinear<T>> : FieldAccessor<T> {};

/// True when T's vertex values may be NaN or infinite (a float dtype, or a paged field of
/// any dtype: the test is exact, never true, for integer values).
template <class T>
inline constexpr bool kMayBeNonFinite = std::is_floating_point_v<typename ValueTraits<T>::base> ||
                                        std::is_same_v<typename ValueTraits<T>::base, PagedValue> ||
                                        std::is_same_v<typename ValueTraits<T>::base, MagnitudeValue>;

template <class T>
struct GridMedium {
  typename FieldAccessor<T>::type field;
  std::int64_t n[3];
  double hi_index[3];  ///< n - 1 as double: the box in voxel space is [0, hi_index]
  const TransferFunction* tf;
  const double* majorant;                     ///< per macrocell, 1 / world unit
  const std::uint8_t* empty_reach = nullptr;  ///< per macrocell (field/empty_reach.h); null: no skipping
  std::int64_t nc[3];
  double cell_edge;  ///< macrocell edge in voxels
  /// Extinction clamp, 1 / world unit (kMaxOpticalThicknessPerVoxel / smallest spacing):
  /// also catches density_scale * opacity overflowing to Inf
  double sigma_max = INFINITY;
  /// A Rectilinear<> Value: value, gradient and the macrocell walk take the general path
  /// (per axis: uniform arithmetic, or the AxisMap); otherwise only the uniform arithmetic
  /// is compiled.
  static constexpr bool kRectilinear = ValueTraits<T>::kRectilinear;
  /// An AmrValue: value() is the hierarchy's (amr_view.h); gradients step one sample of the
  /// finest level in the macrocell.
  static constexpr bool kAmr = ValueTraits<T>::kAmr;
  /// Cell data: the outermost macrocells reach over the outer half cell to the box.
  bool outer_half = false;
  double box_lo[3] = {0.0, 0.0, 0.0};  ///< the medium's box in p: vertex data [0, n - 1]
  double box_hi[3] = {0.0, 0.0, 0.0};
  AxisMap axis[3];  ///< per axis; axis[a].coords == nullptr: uniform

  /// Vertex value, with non-finite values mapped into the TF range (NaN, -Inf -> lo; +Inf -> hi).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double vertex(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return finite_vertex(field.load(i, j, k));
  }
  /// v with NaN, -Inf -> tf->lo and +Inf -> tf->hi (compiled away for integer values).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double finite_vertex(double v) const {
    if constexpr (kMayBeNonFinite<T>) {
      if (!std::isfinite(v)) return v > 0.0 ? tf->hi : tf->lo;
    }
    return v;
  }

  /// Segment and fraction of p along a uniform axis a (clamped to the samples).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE void locate_uniform(int a, double pa, std::int64_t* i0, std::int64_t* i1,
                                                                 double* f) const {
    if (pa >= 0.0 && pa < hi_index[a]) {
      // Inside the samples (the common case): the clamps below would change nothing
      const auto i = static_cast<std::int64_t>(pa);
      *i0 = i;
      *i1 = i + 1;
      *f = pa - static_cast<double>(i);
      return;
    }
    const double x = std::clamp(pa, 0.0, hi_index[a]);
    std::int64_t i = static_cast<std::int64_t>(x);
    if (i > n[a] - 2) i = std::max<std::int64_t>(0, n[a] - 2);
    *i0 = i;
    *i1 = std::min(i + 1, n[a] - 1);
    *f = x - static_cast<double>(i);
    if (*i1 == *i0) *f = 0.0;
  }

  /// Trilinear value at point p (clamped to the samples: over the outer half cell of cell
  /// data, the nearest centre's value along each axis).
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double value(const Vec3& p) const {
    if constexpr (kAmr) {
      return field.value(p, tf->lo, tf->hi);
    } else if constexpr (kRectilinear) {
      return value_rectilinear(p);
    } else {
      std::int64_t i0[3], i1[3];
      double f[3];
      for (int a = 0; a < 3; ++a) locate_uniform(a, p[a], &i0[a], &i1[a], &f[a]);
      return blend(i0, i1, f);
    }
  }

  /// value() where some axis is rectilinear: that axis' segment from its AxisMap.
  TESSERA_HOST_DEVICE double value_rectilinear(const Vec3& p) const {
    std::int64_t i0[3], i1[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      if (axis[a].coords) {
        axis[a].locate(p[a], &i0[a], &f[a]);
        i1[a] = std::min(i0[a] + 1, n[a] - 1);
      } else {
        locate_uniform(a, p[a], &i0[a], &i1[a], &f[a]);
      }
    }
    return blend(i0, i1, f);
  }

  /// The trilinear blend of the 8 samples i0/i1 per axis with fractions f.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double blend(const std::int64_t i0[3], const std::int64_t i1[3],
                                                          const double f[3]) const {
    return trilinear(
        [&](int x, int y, int z)
            __attribute__((always_inline)) { return vertex(x ? i1[0] : i0[0], y ? i1[1] : i0[1], z ? i1[2] : i0[2]); },
        f);
  }

  [[gnu::always_inline]] TESSERA_HOST_DEVICE double u(const Vec3& p) const { return tf->normalise(value(p)); }
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double sigma_t_of_u(double uu) const {
    return std::min(tf->density_scale * tf->opacity.eval(uu), sigma_max);
  }
  [[gnu::always_inline]] TESSERA_HOST_DEVICE double sigma_t(const Vec3& p) const { return sigma_t_of_u(u(p)); }

  /// True for a Value read in place from a dtype's array on uniform axes (no cache, no
  /// AxisMap, no levels): its samples sit at fixed byte offsets from one another.
  static constexpr bool kInPlace = std::is_arithmetic_v<T>;

  /// Gradient of u by central differences one voxel apart (one-sided at the faces), in
  /// units of 1 / voxel. Six field lookups.
  TESSERA_HOST_DEVICE Vec3 gradient_voxel(const Vec3& p) const {
    if constexpr (kInPlace) {
      // One sample from every face (the common case): no clamp bites, each difference spans
      // exactly 2 voxels, and the six lookups share one cell and its 32 samples.
      if (p[0] >= 1.0 && p[0] + 1.0 < hi_index[0] && p[1] >= 1.0 && p[1] + 1.0 < hi_index[1] && p[2] >= 1.0 &&
          p[2] + 1.0 < hi_index[2])
        return gradient_interior(p);
    }
    Vec3 g(0.0);
    double step = 1.0;
    if constexpr (kAmr) step = field.gradient_step(p);
    for (int a = 0; a < 3; ++a) {
      Vec3 pm = p, pp = p;
      pm[a] = std::clamp(p[a] - step, 0.0, hi_index[a]);
      pp[a] = std::clamp(p[a] + step, 0.0, hi_index[a]);
      const double h = pp[a] - pm[a];
      if (h > 0.0) g[a] = (u(pp) - u(pm)) / h;
    }
    return g;
  }

  /// gradient_voxel where p is at least one voxel inside every face (kInPlace): the same
  /// arithmetic as the general path, bit for bit (each lookup locates p +- 1 along its own
  /// axis and keeps p's fractions along the other two; the difference is divided by
  /// (p + 1) - (p - 1)), with no clamp and no index arithmetic per sample: p's cell is found
  /// once and each lookup reads its 8 samples at byte offsets from it.
  TESSERA_HOST_DEVICE Vec3 gradient_interior(const Vec3& p) const {
    std::int64_t i[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      i[a] = static_cast<std::int64_t>(p[a]);
      f[a] = p[a] - static_cast<double>(i[a]);
    }
    const std::int64_t s[3] = {field.sx, field.sy, field.sz};
    const unsigned char* const b = field.base + i[0] * s[0] + i[1] * s[1] + i[2] * s[2];
    const auto at = [&](std::int64_t off) __attribute__((always_inline)) {
      return finite_vertex(decltype(field)::load_at(b + off));
    };
    // u of the blend over the cell whose low corner is `o` bytes from p's, with fractions g
    const auto u_at = [&](std::int64_t o, const double* g) __attribute__((always_inline)) {
      return tf->normalise(trilinear(
          [&](int x, int y, int z) __attribute__((always_inline)) { return at(o + x * s[0] + y * s[1] + z * s[2]); },
          g));
    };
    Vec3 grad;
    for (int a = 0; a < 3; ++a) {
      const double lo = p[a] - 1.0, hi = p[a] + 1.0;
      const auto il = static_cast<std::int64_t>(lo), ih = static_cast<std::int64_t>(hi);
      double gl[3] = {f[0], f[1], f[2]}, gh[3] = {f[0], f[1], f[2]};
      gl[a] = lo - static_cast<double>(il);
      gh[a] = hi - static_cast<double>(ih);
      grad[a] = (u_at((ih - i[a]) * s[a], gh) - u_at((il - i[a]) * s[a], gl)) / (hi - lo);
    }
    return grad;
  }

  /// The gradient of u where some axis is rectilinear: returns it per local sample interval
  /// (a uniform axis as gradient_voxel; a rectilinear one by central differences one local
  /// interval apart, times that interval) and sets *world to the world-space gradient
  /// (inv_spacing: the scene's, for the uniform axes). Six field lookups.
  TESSERA_HOST_DEVICE Vec3 gradient_local(const Vec3& p, const Vec3& inv_spacing, Vec3* world) const {
    Vec3 g(0.0), w(0.0);
    for (int a = 0; a < 3; ++a) {
      Vec3 pm = p, pp = p;
      if (!axis[a].coords) {
        pm[a] = std::clamp(p[a] - 1.0, 0.0, hi_index[a]);
        pp[a] = std::clamp(p[a] + 1.0, 0.0, hi_index[a]);
        const double h = pp[a] - pm[a];
        if (h > 0.0) g[a] = (u(pp) - u(pm)) / h;
        w[a] = g[a] * inv_spacing[a];
      } else {
        const AxisMap& m = axis[a];
        const double local = m.local_spacing(p[a]);
        pm[a] = std::clamp(p[a] - local, m.lo, m.hi);
        pp[a] = std::clamp(p[a] + local, m.lo, m.hi);
        const double h = pp[a] - pm[a];
        if (h > 0.0) w[a] = (u(pp) - u(pm)) / h;
        g[a] = w[a] * local;
      }
    }
    *world = w;
    return g;
  }
};

/// The macrocell holding p along a rectilinear axis (its AxisMap's segment / edge, clamped).
[[gnu::noinline]] TESSERA_HOST_DEVICE inline std::int64_t rectilinear_cell(const AxisMap& ax, double p,
                                                                           std::int64_t edge, std::int64_t nc) {
  std::int64_t seg;
  double f;
  ax.locate(p, &seg, &f);
  return std::clamp<std::int64_t>(seg / edge, 0, nc - 1);
}

/// Where the ray p(t) = ov + t dv leaves the cube of macrocells c +- r (every axis that it
/// moves along; uniform axes, edge E).
TESSERA_HOST_DEVICE inline double cube_exit(const Vec3& ov, const Vec3& dv, const std::int64_t c[3], std::int64_t r,
                                            double E) {
  double t = INFINITY;
  for (int a = 0; a < 3; ++a) {
    if (dv[a] > 0.0) t = std::min(t, (static_cast<double>(c[a] + r + 1) * E - ov[a]) / dv[a]);
    else if (dv[a] < 0.0) t = std::min(t, (static_cast<double>(c[a] - r) * E - ov[a]) / dv[a]);
  }
  return t;
}

/// The macrocell walk of traverse_macrocells (below) one segment at a time, so that a caller can
/// leave it and come back (a GPU thread that runs one tracking step per loop iteration): the
/// same segments in the same order. Trivially copyable; points into the medium.
template <class T>
class MacrocellWalk {
 public:
  struct Segment {
    double ta, tb, majorant;
  };

  /// A walk with no segments (a placeholder to assign a walk to).
  MacrocellWalk() = default;
  [[gnu::always_inline]] TESSERA_HOST_DEVICE MacrocellWalk(const GridMedium<T>& m, const Vec3& ov, const Vec3& dv,
                                                           double t0, double t1)
      : m_m(&m), m_ov(ov), m_dv(dv), m_t(t0), m_t1(t1) {
    m_end = !(t0 < t1);
    if (!m_end) enter(t0);
  }

  /// The next segment, in order along the ray; false once the walk has passed t1 (or left the
  /// medium), and ever after.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE bool next(Segment& s) {
    const GridMedium<T>& m = *m_m;
    while (!m_end) {
      const int a =
          m_t_next[0] < m_t_next[1] ? (m_t_next[0] < m_t_next[2] ? 0 : 2) : (m_t_next[1] < m_t_next[2] ? 1 : 2);
      const double t_exit = std::min(m_t_next[a], m_t1);
      if (t_exit > m_t) {
        const std::int64_t cell = (m_c[2] * m.nc[1] + m_c[1]) * m.nc[0] + m_c[0];
        const double maj = m.majorant[cell];
        if constexpr (!kRect) {
          if (!(maj > 0.0) && m.empty_reach && m.empty_reach[cell] > 2) {
            const double t_skip = std::min(cube_exit(m_ov, m_dv, m_c, m.empty_reach[cell] - 1, m.cell_edge), m_t1);
            if (t_skip > t_exit) {
              s = {m_t, t_skip, 0.0};
              // the walk goes on at the empty cube's exit
              if (t_skip >= m_t1) m_end = true;
              else {
                m_t = t_skip;
                enter(m_t);
              }
              return true;
            }
          }
        }
        s = {m_t, t_exit, maj};
        m_t = t_exit;
        m_end = !advance(a);  // past the segment's cell, along its exit axis
        return true;
      }
      m_end = !advance(a);
    }
    return false;
  }

 private:
  static constexpr bool kRect = GridMedium<T>::kRectilinear;  // a uniform Value tests no AxisMap

  /// The cell holding p(t) and, per axis, the distance of its next wall.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE void enter(double t) {
    const GridMedium<T>& m = *m_m;
    const double E = m.cell_edge;
    const Vec3 p = m_ov + t * m_dv;
    for (int a = 0; a < 3; ++a) {
      const AxisMap& ax = m.axis[a];
      const bool rect = kRect && ax.coords != nullptr;
      m_c[a] = rect ? rectilinear_cell(ax, p[a], static_cast<std::int64_t>(E), m.nc[a])
                    : std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(p[a] / E)), 0, m.nc[a] - 1);
      if (m_dv[a] > 0.0) {
        m_step[a] = 1;
        m_t_next[a] = ((rect ? ax.walls[m_c[a] + 1] : (m_c[a] + 1) * E) - m_ov[a]) / m_dv[a];
        m_t_delta[a] = E / m_dv[a];
      } else if (m_dv[a] < 0.0) {
        m_step[a] = -1;
        m_t_next[a] = ((rect ? ax.walls[m_c[a]] : m_c[a] * E) - m_ov[a]) / m_dv[a];
        m_t_delta[a] = -E / m_dv[a];
      } else {
        m_step[a] = 0;
        m_t_next[a] = INFINITY;
        m_t_delta[a] = INFINITY;
      }
    }
  }

  /// Into the next cell along axis a; false at t1 or past the medium's last cell.
  [[gnu::always_inline]] TESSERA_HOST_DEVICE bool advance(int a) {
    const GridMedium<T>& m = *m_m;
    if (m_t >= m_t1) return false;
    m_c[a] += m_step[a];
    if (m_c[a] < 0 || m_c[a] >= m.nc[a]) {
      // Past the outermost macrocell: the end of the medium, or its outer half cell
      if (!m.outer_half) return false;
      m_c[a] -= m_step[a];
      m_t_next[a] = INFINITY;
      return true;
    }
    if (kRect && m.axis[a].coords)
      m_t_next[a] = (m.axis[a].walls[m_step[a] > 0 ? m_c[a] + 1 : m_c[a]] - m_ov[a]) / m_dv[a];
    else m_t_next[a] += m_t_delta[a];
    return true;
  }

  const GridMedium<T>* m_m = nullptr;
  Vec3 m_ov{0.0}, m_dv{0.0};
  double m_t = 0.0, m_t1 = 0.0;
  std::int64_t m_c[3] = {0, 0, 0}, m_step[3] = {0, 0, 0};
  double m_t_next[3] = {INFINITY, INFINITY, INFINITY}, m_t_delta[3] = {INFINITY, INFINITY, INFINITY};
  bool m_end = true;  ///< past t1 or the medium: no more segments
};

/// Walks the macrocells a ray crosses between world distances t0 < t1, calling
/// fn(t_enter, t_exit, majorant) for each in order until fn returns true (stop).
/// Ray in the medium's p space: p(t) = ov + t * dv. Returns true if fn stopped the walk.
/// A uniform axis steps E at a time; a rectilinear one from wall to wall of its AxisMap. For
/// cell data the outermost macrocells reach on to the box (the outer half cell).
/// Empty space (majorant 0) may come as one segment spanning several cells: where the
/// medium has an empty-reach table (field/empty_reach.h) and every axis is uniform, an empty
/// cell of reach R >= 3 hands fn the ray's whole way through its empty cube of cells c +- (R - 1)
/// at once, and the walk restarts at the cube's exit (a smaller cube does not pay for the
/// restart). The segments still tile [t0, t1]. (MacrocellWalk, one segment at a time.)
template <class T, class Fn>
TESSERA_HOST_DEVICE bool traverse_macrocells(const GridMedium<T>& m, const Vec3& ov, const Vec3& dv, double t0,
                                             double t1, Fn&& fn) {
  MacrocellWalk<T> walk(m, ov, dv, t0, t1);
  typename MacrocellWalk<T>::Segment s;
  while (walk.next(s))
    if (fn(s.ta, s.tb, s.majorant)) return true;
  return false;
}

}  // namespace tessera
