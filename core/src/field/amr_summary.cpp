/// amr_summary (amr.h): the macrocell value ranges of a hierarchy.
///
/// A sample i of level l (along an axis with n samples) takes part in the stencils of the
/// stencil cells i - 1 and i, i.e. of the points with q in [i - 1, i + 1] (q = p * R_l + shift,
/// amr_view.h), (q in the open interval (i - 1, i + 1)), and
/// through the clamp of every point beyond the level's first or last sample. Its value
/// therefore goes into the range of every level-0 macrocell that p interval meets, whichever
/// level a point there ends up taking:
/// conservative whatever the coarse-fine rule selects, and the same for any cut into patches
/// (each sample counts once per level, and min, max, or and sum are exact in any order).
#include <tessera/amr.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tessera {
namespace {

std::int64_t cells_along(std::int64_t dims, int edge) {
  return std::max<std::int64_t>(1, (dims - 1 + edge - 1) / edge);
}

}  // namespace

FieldSummary::Parts amr_summary_parts(const AmrField& f, Association assoc, int edge) {
  FieldSummary::Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = cells_along(f.dims[a], edge);
  const std::size_t ncell = static_cast<std::size_t>(parts.cells[0] * parts.cells[1] * parts.cells[2]);
  parts.lo.assign(ncell, INFINITY);
  parts.hi.assign(ncell, -INFINITY);
  parts.flags.assign(ncell, 0);
  const double E = static_cast<double>(edge);
  std::vector<std::int64_t> c0[3], c1[3];
  for (const AmrPatch& p : f.patches) {
    if (p.view.data == nullptr) continue;  // another rank's (distributed mode)
    parts.elements += static_cast<std::uint64_t>(p.view.vertex_count());
    const double R = static_cast<double>(f.scale(p.level));
    const double shift = assoc == Association::Cell ? 0.5 * R - 0.5 : 0.0;
    // Per axis, each of the patch's samples' macrocell range
    for (int a = 0; a < 3; ++a) {
      const std::int64_t n = f.level_dims(p.level, a, assoc), d = p.view.dims[a];
      c0[a].resize(static_cast<std::size_t>(d));
      c1[a].resize(static_cast<std::size_t>(d));
      for (std::int64_t s = 0; s < d; ++s) {
        const std::int64_t i = p.offset[a] + s;
        // Points with q in the open interval (i - 1, i + 1) weigh sample i: the macrocells
        // [c E, (c + 1) E] that interval meets (as FieldSummary's vertices cE ..= (c + 1)E)
        const double plo = i == 0 ? -INFINITY : (static_cast<double>(i - 1) - shift) / R;
        const double phi = i == n - 1 ? INFINITY : (static_cast<double>(i + 1) - shift) / R;
        const auto clamp_cell = [&](double x) {
          if (!(x > 0.0)) return std::int64_t{0};
          return std::min<std::int64_t>(static_cast<std::int64_t>(std::min(x, 9e18)), parts.cells[a] - 1);
        };
        c0[a][static_cast<std::size_t>(s)] = clamp_cell(std::floor(plo / E));
        c1[a][static_cast<std::size_t>(s)] = clamp_cell(std::ceil(phi / E) - 1.0);
      }
    }
    dispatch_dtype(p.view, [&](auto view) {
      for (std::int64_t k = 0; k < p.view.dims[2]; ++k)
        for (std::int64_t j = 0; j < p.view.dims[1]; ++j)
          for (std::int64_t i = 0; i < p.view.dims[0]; ++i) {
            const double v = view.load(i, j, k) + 0.0;  // -0.0 -> +0.0 (FieldSummary's convention)
            std::uint8_t flag = 0;
            if (std::isnan(v)) {
              flag = 1;
              ++parts.nan;
            } else if (std::isinf(v)) {
              flag = v > 0 ? 2 : 4;
            } else {
              parts.vmin = std::min(parts.vmin, v);
              parts.vmax = std::max(parts.vmax, v);
            }
            for (std::int64_t z = c0[2][k]; z <= c1[2][k]; ++z)
              for (std::int64_t y = c0[1][j]; y <= c1[1][j]; ++y)
                for (std::int64_t x = c0[0][i]; x <= c1[0][i]; ++x) {
                  const std::size_t c = static_cast<std::size_t>((z * parts.cells[1] + y) * parts.cells[0] + x);
                  if (flag) {
                    parts.flags[c] |= flag;
                  } else {
                    parts.lo[c] = std::min(parts.lo[c], v);
                    parts.hi[c] = std::max(parts.hi[c], v);
                  }
                }
          }
    });
  }
  return parts;
}

std::shared_ptr<const FieldSummary> amr_summary(const AmrField& f, Association assoc, int edge) {
  check_amr(f, assoc);
  FieldLayout layout;
  layout.dtype = f.dtype;
  for (int a = 0; a < 3; ++a) layout.dims[a] = f.dims[a];
  return FieldSummary::from_parts(amr_summary_parts(f, assoc, edge), layout, edge);
}

}  // namespace tessera
