/// The index spaces of refinement levels and the hierarchy's structural checks (amr.h).
///
/// Overlap and nesting are found through a bin grid per level (about as many bins as the
/// level has patches, at most 2^20): a patch is compared only with the patches that share a
/// bin with it. Patches of one level are disjoint once checked, so the bins a level's patches
/// occupy add up to about the bins plus the patches' surfaces: linear in the patch count.
#include <tessera/amr.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {
namespace {

const char* const kAxis[3] = {"x", "y", "z"};

std::string box_text(const std::int64_t lo[3], const std::int64_t hi[3]) {
  std::string s;
  for (int a = 0; a < 3; ++a) {
    if (a) s += " x ";
    s += "[" + std::to_string(lo[a]) + ", " + std::to_string(hi[a]) + ")";
  }
  return s;
}

struct Box {
  std::int64_t lo[3], hi[3];
  bool intersects(const Box& o) const {
    for (int a = 0; a < 3; ++a)
      if (hi[a] <= o.lo[a] || o.hi[a] <= lo[a]) return false;
    return true;
  }
  std::int64_t overlap_volume(const Box& o) const {
    std::int64_t v = 1;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t w = std::min(hi[a], o.hi[a]) - std::max(lo[a], o.lo[a]);
      if (w <= 0) return 0;
      v *= w;
    }
    return v;
  }
};

/// The patches of one level, binned.
class LevelBins {
 public:
  LevelBins(const std::int64_t extent[3], std::size_t patches) {
    const double target = std::clamp<double>(2.0 * static_cast<double>(patches), 1.0, double(1 << 20));
    const double volume = double(extent[0]) * double(extent[1]) * double(extent[2]);
    const double edge = std::max(1.0, std::cbrt(volume / target));
    for (int a = 0; a < 3; ++a) {
      m_edge[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(edge)));
      m_n[a] = std::max<std::int64_t>(1, (extent[a] + m_edge[a] - 1) / m_edge[a]);
    }
    m_bins.resize(static_cast<std::size_t>(m_n[0] * m_n[1] * m_n[2]));
  }

  /// Calls fn(bin's patch list) for every bin `b` touches (b inside the extent).
  template <class Fn>
  void for_bins(const Box& b, Fn&& fn) {
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp<std::int64_t>(b.lo[a] / m_edge[a], 0, m_n[a] - 1);
      hi[a] = std::clamp<std::int64_t>((b.hi[a] - 1) / m_edge[a], 0, m_n[a] - 1);
    }
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
          fn(m_bins[static_cast<std::size_t>((z * m_n[1] + y) * m_n[0] + x)]);
  }

 private:
  std::int64_t m_edge[3], m_n[3];
  std::vector<std::vector<std::size_t>> m_bins;
};

}  // namespace

std::int64_t AmrField::scale(int l) const {
  std::int64_t r = 1;
  for (int i = 0; i < l && i < kMaxAmrLevels - 1; ++i) r *= ratio[i];
  return r;
}

std::int64_t AmrField::level_dims(int l, int a, Association assoc) const {
  const std::int64_t r = scale(l);
  return assoc == Association::Cell ? dims[a] * r : (dims[a] - 1) * r + 1;
}

void check_amr_boxes(const AmrField& meta, Association assoc, std::span<const AmrBox> boxes,
                     const std::function<std::string(std::size_t)>& name) {
  const auto fail = [](const std::string& m) { throw std::invalid_argument(m); };
  if (meta.nlevels < 1 || meta.nlevels > kMaxAmrLevels)
    fail("nlevels " + std::to_string(meta.nlevels) + " is outside [1, " + std::to_string(kMaxAmrLevels) + "]");
  for (int l = 0; l + 1 < meta.nlevels; ++l)
    if (meta.ratio[l] != 2 && meta.ratio[l] != 4)
      fail("refinement[" + std::to_string(l) + "] = " + std::to_string(meta.ratio[l]) +
           ": a level's refinement ratio must be 2 or 4");
  for (int a = 0; a < 3; ++a)
    if (meta.dims[a] < 1 || meta.dims[a] > (std::int64_t{1} << 31))
      fail(std::string("level-0 dims along ") + kAxis[a] + " = " + std::to_string(meta.dims[a]) +
           " is outside [1, 2^31]");
  // Each level's extent must stay far from int64 overflow (2^40 elements per axis)
  std::int64_t extent[kMaxAmrLevels][3];
  for (int l = 0; l < meta.nlevels; ++l)
    for (int a = 0; a < 3; ++a) {
      extent[l][a] = meta.level_dims(l, a, assoc);
      if (extent[l][a] > (std::int64_t{1} << 40))
        fail("level " + std::to_string(l) + " has " + std::to_string(extent[l][a]) + " elements along " + kAxis[a] +
             ": more than 2^40");
    }
  // Each box alone
  std::vector<std::vector<std::size_t>> by_level(static_cast<std::size_t>(meta.nlevels));
  for (std::size_t n = 0; n < boxes.size(); ++n) {
    const AmrBox& b = boxes[n];
    if (b.level < 0 || b.level >= meta.nlevels)
      fail(name(n) + ": level " + std::to_string(b.level) + " is outside [0, " + std::to_string(meta.nlevels) + ")");
    for (int a = 0; a < 3; ++a) {
      if (b.dims[a] < 1) fail(name(n) + ": no real element along " + kAxis[a]);
      if (b.offset[a] < 0 || b.offset[a] > extent[b.level][a] - b.dims[a])
        fail(name(n) + ": elements [" + std::to_string(b.offset[a]) + ", " + std::to_string(b.offset[a] + b.dims[a]) +
             ") along " + kAxis[a] + " leave level " + std::to_string(b.level) + "'s extent [0, " +
             std::to_string(extent[b.level][a]) + ")");
    }
    by_level[static_cast<std::size_t>(b.level)].push_back(n);
  }
  const auto box_of = [&](std::size_t n) {
    Box r;
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = boxes[n].offset[a];
      r.hi[a] = boxes[n].offset[a] + boxes[n].dims[a];
    }
    return r;
  };
  // Per level: no overlap; level 0 covers the mesh; level l+1 inside level l
  std::vector<LevelBins> bins;
  bins.reserve(static_cast<std::size_t>(meta.nlevels));
  for (int l = 0; l < meta.nlevels; ++l) {
    const auto& ids = by_level[static_cast<std::size_t>(l)];
    bins.emplace_back(extent[l], ids.size());
    LevelBins& lb = bins.back();
    double volume = 0.0;
    for (std::size_t n : ids) {
      const Box b = box_of(n);
      lb.for_bins(b, [&](std::vector<std::size_t>& bin) {
        for (std::size_t m : bin)
          if (m != n && b.intersects(box_of(m)))
            fail(name(m) + " and " + name(n) + " overlap at level " + std::to_string(l) + ": elements " +
                 box_text(box_of(m).lo, box_of(m).hi) + " and " + box_text(b.lo, b.hi));
        if (bin.empty() || bin.back() != n) bin.push_back(n);
      });
      volume += double(b.hi[0] - b.lo[0]) * double(b.hi[1] - b.lo[1]) * double(b.hi[2] - b.lo[2]);
    }
    if (l == 0) {
      const double whole = double(extent[0][0]) * double(extent[0][1]) * double(extent[0][2]);
      if (volume != whole)
        fail("level 0 does not cover the mesh: its patches hold " + std::to_string(static_cast<long long>(volume)) +
             " of the " + std::to_string(static_cast<long long>(whole)) + " elements of " +
             std::to_string(extent[0][0]) + "x" + std::to_string(extent[0][1]) + "x" + std::to_string(extent[0][2]));
      continue;
    }
    // Nesting: each patch of level l, coarsened outward to level l-1, is covered by level l-1
    const std::int64_t r = meta.ratio[l - 1];
    std::vector<std::size_t> seen(boxes.size(), SIZE_MAX);
    for (std::size_t n : ids) {
      const Box f = box_of(n);
      Box c;
      for (int a = 0; a < 3; ++a) {
        c.lo[a] = f.lo[a] / r;
        // Vertex data: the coarse vertices around the fine vertex box; cell data: the coarse
        // cells holding the fine cells
        c.hi[a] = assoc == Association::Cell ? (f.hi[a] + r - 1) / r : (f.hi[a] - 1 + r - 1) / r + 1;
        c.hi[a] = std::min(c.hi[a], extent[l - 1][a]);
      }
      std::int64_t covered = 0;
      bins[static_cast<std::size_t>(l - 1)].for_bins(c, [&](std::vector<std::size_t>& bin) {
        for (std::size_t m : bin)
          if (seen[m] != n) {
            seen[m] = n;
            covered += c.overlap_volume(box_of(m));
          }
      });
      const std::int64_t need = (c.hi[0] - c.lo[0]) * (c.hi[1] - c.lo[1]) * (c.hi[2] - c.lo[2]);
      if (covered != need)
        fail(name(n) + " (level " + std::to_string(l) + ", elements " + box_text(f.lo, f.hi) +
             ") is not inside the region level " + std::to_string(l - 1) + " covers: level " + std::to_string(l - 1) +
             " holds " + std::to_string(covered) + " of the " + std::to_string(need) + " elements " +
             box_text(c.lo, c.hi) + " under it");
    }
  }
}

AmrVirtualLayout amr_virtual_layout(const AmrField& meta, Association assoc, std::span<const AmrBox> boxes,
                                    int brick_shift) {
  (void)assoc;
  AmrVirtualLayout v;
  const std::int64_t brick = std::int64_t{1} << brick_shift;
  std::int64_t x = 0, y = 1, z = 1;
  for (int l = 0; l < meta.nlevels && l < kMaxAmrLevels; ++l) {
    std::int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (const AmrBox& b : boxes)
      if (b.level == l)
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], b.offset[a]);
          hi[a] = std::max(hi[a], b.offset[a] + b.dims[a]);
        }
    if (lo[0] > hi[0]) continue;  // no patch at this level
    v.base[l][0] = x - lo[0];
    v.base[l][1] = -lo[1];
    v.base[l][2] = -lo[2];
    x += (hi[0] - lo[0] + brick - 1) / brick * brick;
    y = std::max(y, hi[1] - lo[1]);
    z = std::max(z, hi[2] - lo[2]);
    if (x > (std::int64_t{1} << 40))
      throw std::invalid_argument("refinement levels: the distributed grid of the levels' patches would exceed 2^40 "
                                  "elements along x");
  }
  v.dims[0] = std::max<std::int64_t>(x, 1);
  v.dims[1] = y;
  v.dims[2] = z;
  return v;
}

void check_amr(const AmrField& field, Association assoc) {
  const auto name = [&](std::size_t n) {
    return n < field.names.size() && !field.names[n].empty() ? field.names[n] : "patch " + std::to_string(n);
  };
  std::vector<AmrBox> boxes(field.patches.size());
  for (std::size_t n = 0; n < field.patches.size(); ++n) {
    const AmrPatch& p = field.patches[n];
    if (p.view.data == nullptr && field.cache != nullptr) {
      // Another rank's patch (distributed mode): its dims only
      for (int a = 0; a < 3; ++a)
        if (p.view.dims[a] < 1) throw std::invalid_argument(name(n) + ": no real element along " + kAxis[a]);
    } else {
      p.view.validate(name(n));
    }
    if (p.view.dtype != field.dtype)
      throw std::invalid_argument(name(n) + " is " + dtype_name(p.view.dtype) + ", the hierarchy " +
                                  dtype_name(field.dtype));
    boxes[n].level = p.level;
    for (int a = 0; a < 3; ++a) {
      boxes[n].offset[a] = p.offset[a];
      boxes[n].dims[a] = p.view.dims[a];
    }
  }
  check_amr_boxes(field, assoc, boxes, name);
}

}  // namespace tessera
