#pragma once
/// Test input for refinement levels through tessera_execute_domains: a hierarchy (level-0
/// dims, association, ratios) and patches given as boxes of their level, each patch its own
/// float32 array with NaN ghost layers (never read) in a layout of its own (i fastest, or k
/// fastest), its values a function of the world position of each element (a vertex, or a
/// cell's centre) at its level. The mesh spans [-0.5, 0.5]^3.
#include "domain_cuts.h"

#include <tessera/tessera.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <numeric>
#include <vector>

namespace tessera_test {

struct AmrBoxSpec {
  int level;
  Dims offset;  ///< first element, at its level
  Dims dims;    ///< elements, at its level
};

/// A hierarchy's mesh: level-0 dims, association, ratios (nlevels = ratios + 1).
struct AmrMeshSpec {
  Dims g;
  tessera_association assoc;
  std::vector<int> ratios;

  int nlevels() const { return static_cast<int>(ratios.size()) + 1; }
  std::int64_t scale(int level) const {
    std::int64_t r = 1;
    for (int l = 0; l < level; ++l) r *= ratios[static_cast<std::size_t>(l)];
    return r;
  }
  /// Elements of `level` along axis a.
  std::int64_t extent(int level, int a) const {
    return assoc == TESSERA_CELL ? g[a] * scale(level) : (g[a] - 1) * scale(level) + 1;
  }
  double spacing(int a) const { return 1.0 / static_cast<double>(assoc == TESSERA_CELL ? g[a] : g[a] - 1); }
  /// World coordinate along a of element i of `level`.
  double position(int level, int a, std::int64_t i) const {
    const double h = spacing(a) / static_cast<double>(scale(level));
    return -0.5 + (static_cast<double>(i) + (assoc == TESSERA_CELL ? 0.5 : 0.0)) * h;
  }
  /// The mesh (its refinement points into this spec's ratios).
  tessera_mesh mesh() const {
    tessera_mesh m = unit_mesh(g, assoc);
    m.nlevels = nlevels();
    m.refinement = ratios.empty() ? nullptr : ratios.data();
    return m;
  }
};

using WorldField = std::function<double(double, double, double)>;
/// A value per level and world position (data that differs between levels).
using LevelField = std::function<double(int, double, double, double)>;

/// Patches as a simulation holds them (addresses stable: the descriptors point into them).
class HeldPatches {
 public:
  HeldPatches(const AmrMeshSpec& spec, const std::vector<AmrBoxSpec>& boxes, const WorldField& f, int ghosts = 1)
      : HeldPatches(spec, boxes, LevelField([&f](int, double x, double y, double z) { return f(x, y, z); }), ghosts) {}
  HeldPatches(const AmrMeshSpec& spec, const std::vector<AmrBoxSpec>& boxes, const LevelField& f, int ghosts = 1) {
    for (std::size_t n = 0; n < boxes.size(); ++n) add(spec, boxes[n], f, ghosts, n % 2 == 1);
  }
  /// Every patch's descriptor, in the order `order` lists the patches (all, in their order,
  /// when empty).
  std::vector<tessera_domain> all(const std::vector<std::size_t>& order = {}) const {
    std::vector<std::size_t> o = order;
    if (o.empty()) {
      o.resize(m_held.size());
      std::iota(o.begin(), o.end(), std::size_t{0});
    }
    std::vector<tessera_domain> out;
    for (std::size_t n : o) out.push_back(m_held[n].domain);
    return out;
  }
  /// The descriptors of the patches n with owner(n) == rank.
  std::vector<tessera_domain> of_rank(int rank, const std::function<int(std::size_t)>& owner) const {
    std::vector<tessera_domain> out;
    for (std::size_t n = 0; n < m_held.size(); ++n)
      if (owner(n) == rank) out.push_back(m_held[n].domain);
    return out;
  }
  std::size_t size() const { return m_held.size(); }

 private:
  struct Held {
    std::vector<float> data;
    tessera_field field{};
    tessera_domain domain{};
  };
  void add(const AmrMeshSpec& spec, const AmrBoxSpec& b, const LevelField& f, int ghosts, bool k_fastest) {
    Held& h = m_held.emplace_back();
    Dims d;
    for (int a = 0; a < 3; ++a) d[a] = b.dims[a] + 2 * ghosts;
    h.data.assign(static_cast<std::size_t>(d[0] * d[1] * d[2]), std::numeric_limits<float>::quiet_NaN());
    std::int64_t stride[3];
    if (k_fastest) {
      stride[2] = 1, stride[1] = d[2], stride[0] = d[2] * d[1];
    } else {
      stride[0] = 1, stride[1] = d[0], stride[2] = d[0] * d[1];
    }
    for (std::int64_t k = 0; k < b.dims[2]; ++k)
      for (std::int64_t j = 0; j < b.dims[1]; ++j)
        for (std::int64_t i = 0; i < b.dims[0]; ++i)
          h.data[static_cast<std::size_t>((i + ghosts) * stride[0] + (j + ghosts) * stride[1] +
                                          (k + ghosts) * stride[2])] =
              static_cast<float>(f(b.level, spec.position(b.level, 0, b.offset[0] + i),
                                   spec.position(b.level, 1, b.offset[1] + j),
                                   spec.position(b.level, 2, b.offset[2] + k)));
    h.field.name = "density";
    h.field.data = h.data.data();
    h.field.dtype = TESSERA_FLOAT32;
    for (int a = 0; a < 3; ++a) {
      h.field.dims[a] = d[a];
      h.field.byte_strides[a] = 4 * stride[a];
      h.field.ghosts_lo[a] = h.field.ghosts_hi[a] = ghosts;
      h.domain.offset[a] = b.offset[a];
    }
    h.domain.level = b.level;
    h.domain.fields = &h.field;
    h.domain.nfields = 1;
  }
  std::deque<Held> m_held;
};

/// `box` cut into `parts` uneven slabs along axis a (parts <= box.dims[a]).
inline std::vector<AmrBoxSpec> slabs(const AmrBoxSpec& box, int a, int parts) {
  std::vector<AmrBoxSpec> out;
  const std::int64_t n = box.dims[a];
  std::int64_t at = 0;
  for (int p = 0; p < parts; ++p) {
    // uneven: sizes grow with p (weights 1, 2, 3, ...)
    const std::int64_t total_w = static_cast<std::int64_t>(parts) * (parts + 1) / 2;
    const std::int64_t w = std::int64_t{p} * (p + 1) / 2 + p + 1;  // cumulative weight after p
    const std::int64_t end = p + 1 == parts ? n : std::max(at + 1, n * w / total_w);
    AmrBoxSpec s = box;
    s.offset[a] = box.offset[a] + at;
    s.dims[a] = end - at;
    out.push_back(s);
    at = end;
  }
  return out;
}

/// The level-(l+1) box refining level-l cells [lo, hi) (each axis).
inline AmrBoxSpec refine(const AmrMeshSpec& s, int l, const Dims& lo, const Dims& hi) {
  const std::int64_t r = s.ratios[static_cast<std::size_t>(l)];
  AmrBoxSpec b{l + 1, {}, {}};
  for (int a = 0; a < 3; ++a) {
    b.offset[a] = lo[a] * r;
    b.dims[a] = (hi[a] - lo[a]) * r + (s.assoc == TESSERA_CELL ? 0 : 1);
  }
  return b;
}

inline AmrBoxSpec whole_level0(const AmrMeshSpec& s) { return AmrBoxSpec{0, {0, 0, 0}, s.g}; }

/// A hierarchy and two cuts of its levels into patches: `one` (a patch per level) and `many`
/// (level 0 in 3 slabs along k, level 1 in 5 uneven slabs along i, level 2 in 4 along j),
/// `many` listed in another order (reversed, then every other patch moved to the front).
struct Hierarchy {
  AmrMeshSpec spec;
  std::vector<AmrBoxSpec> one, many;
  std::vector<std::size_t> many_order;
};

inline Hierarchy hierarchy(int nlevels, tessera_association assoc) {
  Hierarchy h;
  const bool cell = assoc == TESSERA_CELL;
  h.spec.assoc = assoc;
  h.spec.g = cell ? Dims{16, 14, 12} : Dims{17, 15, 13};
  h.spec.ratios = nlevels == 2 ? std::vector<int>{2} : std::vector<int>{2, 4};
  h.one.push_back(whole_level0(h.spec));
  h.one.push_back(refine(h.spec, 0, {3, 3, 2}, {13, 12, 11}));
  if (nlevels == 3) h.one.push_back(refine(h.spec, 1, {10, 9, 8}, {18, 17, 14}));
  const int parts[3] = {3, 5, 4}, axis[3] = {2, 0, 1};
  for (std::size_t l = 0; l < h.one.size(); ++l)
    for (const AmrBoxSpec& b : slabs(h.one[l], axis[l], parts[l])) h.many.push_back(b);
  for (std::size_t n = h.many.size(); n-- > 0;)
    if (n % 2 == 1) h.many_order.push_back(n);
  for (std::size_t n = h.many.size(); n-- > 0;)
    if (n % 2 == 0) h.many_order.push_back(n);
  return h;
}

/// 8 levels of ratio 4 over 4^3 cells; each finer level two 2^3-cell patches at opposite
/// corners of the one below: 113 values in all, but each level's lookup table spans its whole
/// extent (the finest 65536 cells per axis), about 6 MiB of tables.
struct DeepCorners {
  AmrMeshSpec spec{{4, 4, 4}, TESSERA_CELL, {4, 4, 4, 4, 4, 4, 4}};
  std::vector<AmrBoxSpec> boxes;
  DeepCorners() {
    boxes.push_back({0, {0, 0, 0}, {4, 4, 4}});
    for (int l = 1; l < 8; ++l) {
      const std::int64_t far = spec.extent(l, 0) - 2;
      boxes.push_back({l, {0, 0, 0}, {2, 2, 2}});
      boxes.push_back({l, {far, far, far}, {2, 2, 2}});
    }
  }
};

/// Integer-valued blobs in [0, 250] over the world position (not linear: the finer levels
/// hold detail that interpolating level 0 misses).
inline double blobs(double x, double y, double z) {
  const double r2 = (x + 0.05) * (x + 0.05) + 1.3 * y * y + (z - 0.05) * (z - 0.05);
  return std::round(250.0 * std::exp(-r2 / 0.07) + 40.0 * std::exp(-((x - 0.3) * (x - 0.3) + y * y) / 0.02));
}

}  // namespace tessera_test
