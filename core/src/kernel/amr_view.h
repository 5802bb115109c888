#pragma once
/// AmrFieldView: how the kernels read a hierarchy of refinement levels (amr.h), in the medium's
/// p space of level 0 (grid_medium.h: sample i of level 0 at p = i). Trivially copyable; it
/// points into the tables that prepare() built (scene/amr_tables.h) and into the patches.
///
/// A lookup at p: the macrocell's level table says the finest level any patch reaches there;
/// from that level down, the level's stencil table (one entry per 2^shift stencil cells of
/// the level) says at once whether the point's stencil lies wholly in one patch (the common
/// case: 8 strided loads in place), in no patch (next level), or across patches (each sample
/// found among the entry's few candidate patches). Level 0 covers the mesh, so the walk ends.
/// No search over levels' patches, no allocation, no virtual call.
#include <tessera/brick_cache.h>
#include <tessera/field_view.h>
#include <tessera/host_device.h>
#include <tessera/math.h>

#include "kernel/trilinear.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace tessera {

/// Where a patch's samples are: global sample (i, j, k) of its level at byte address
/// origin + i s0 + j s1 + k s2, for lo <= (i, j, k) < hi; or, for another rank's patch
/// (remote, distributed mode), at virtual element vbase + (i, j, k) of the paged grid.
struct AmrPatchAddress {
  std::intptr_t origin = 0;
  bool remote = false;
  std::int64_t vbase[3] = {0, 0, 0};
  std::int64_t s[3] = {0, 0, 0};
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  TESSERA_HOST_DEVICE bool holds(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i >= lo[0] && i < hi[0] && j >= lo[1] && j < hi[1] && k >= lo[2] && k < hi[2];
  }
  TESSERA_HOST_DEVICE const unsigned char* at(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return reinterpret_cast<const unsigned char*>(origin + static_cast<std::intptr_t>(i * s[0] + j * s[1] + k * s[2]));
  }
};

/// One level's lookup data.
struct AmrLevelView {
  std::int64_t n[3] = {1, 1, 1};   ///< the level's samples per axis
  double hi_index[3] = {0, 0, 0};  ///< n - 1
  double scale = 1.0;              ///< q = p * scale + shift: the level's sample index space
  double shift = 0.0;
  /// Stencil table: entry per table cell of 2^shift stencil cells, x fastest, from stencil cell
  /// lo: >= 0 the patch holding every sample of every stencil of the cell; -1 none;
  /// <= -2 candidates cand[first[-2 - e]] .. cand[first[-1 - e]]
  const std::int32_t* table = nullptr;
  std::int64_t lo[3] = {0, 0, 0};
  std::uint64_t cells[3] = {0, 0, 0};
  int shift_bits = 0;
  const std::uint32_t* first = nullptr;
  const std::int32_t* cand = nullptr;
};

struct AmrFieldView {
  DType dtype = DType::Float32;
  int nlevels = 0;  ///< 0: not a hierarchy
  AmrLevelView level[8];
  const AmrPatchAddress* patch = nullptr;
  /// Distributed mode: the virtual grid (amr.h AmrVirtualLayout) remote patches are read from.
  PagedFieldView paged;
  /// Per macrocell of the majorant grid (x fastest): the finest level any patch reaches there.
  const std::uint8_t* finest = nullptr;
  std::int64_t nc[3] = {1, 1, 1};
  double inv_edge = 1.0;  ///< 1 / macrocell edge (level-0 samples)

  /// The finest level a patch reaches in p's macrocell.
  TESSERA_HOST_DEVICE int finest_at(const Vec3& p) const {
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(p[a] * inv_edge)), 0, nc[a] - 1);
    return finest[(c[2] * nc[1] + c[1]) * nc[0] + c[0]];
  }

  /// The hierarchy's value at p (the finest level whose stencil is present), non-finite
  /// samples mapped as GridMedium::vertex does (NaN, -Inf -> nf_lo; +Inf -> nf_hi).
  TESSERA_HOST_DEVICE double value(const Vec3& p, double nf_lo, double nf_hi) const {
    double v = 0.0;
    for (int l = finest_at(p); l > 0; --l)
      if (value_at(l, p, nf_lo, nf_hi, &v)) return v;
    value_at(0, p, nf_lo, nf_hi, &v);  // level 0 covers the mesh (check_amr)
    return v;
  }

  /// Central-difference step for gradients, in level-0 samples: one sample of the finest level
  /// in p's macrocell.
  TESSERA_HOST_DEVICE double gradient_step(const Vec3& p) const { return 1.0 / level[finest_at(p)].scale; }

  /// Sample (i, j, k) of patch P's level (inside P), as double.
  TESSERA_HOST_DEVICE double load(const AmrPatchAddress& P, std::int64_t i, std::int64_t j, std::int64_t k) const {
#if defined(__CUDA_ARCH__)
    // The device holds no brick cache: render_tiles_cuda refuses a hierarchy with remote patches
    return detail::load_as_double(dtype, P.at(i, j, k));
#else
    if (!P.remote) [[likely]]
      return detail::load_as_double(dtype, P.at(i, j, k));
    return paged.load(P.vbase[0] + i, P.vbase[1] + j, P.vbase[2] + k);
#endif
  }

  /// The value of level l at p into *out if its stencil is present there.
  TESSERA_HOST_DEVICE bool value_at(int l, const Vec3& p, double nf_lo, double nf_hi, double* out) const {
    const AmrLevelView& L = level[l];
    std::int64_t i0[3], i1[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      const double x = std::clamp(p[a] * L.scale + L.shift, 0.0, L.hi_index[a]);
      std::int64_t s = static_cast<std::int64_t>(x);
      if (s > L.n[a] - 2) s = std::max<std::int64_t>(0, L.n[a] - 2);
      i0[a] = s;
      i1[a] = std::min(s + 1, L.n[a] - 1);
      f[a] = i1[a] == s ? 0.0 : x - static_cast<double>(s);
    }
    std::uint64_t t[3];
    for (int a = 0; a < 3; ++a) {
      t[a] = static_cast<std::uint64_t>(i0[a] - L.lo[a]) >> L.shift_bits;
      if (t[a] >= L.cells[a]) return false;
    }
    const std::int32_t e = L.table[(t[2] * L.cells[1] + t[1]) * L.cells[0] + t[0]];
    if (e == -1) return false;
    double c[8];
    if (e >= 0) {
      const AmrPatchAddress& P = patch[e];
      for (int q = 0; q < 8; ++q) c[q] = load(P, q & 1 ? i1[0] : i0[0], q & 2 ? i1[1] : i0[1], q & 4 ? i1[2] : i0[2]);
    } else {
      const std::uint32_t b = L.first[-2 - e], end = L.first[-1 - e];
      for (int q = 0; q < 8; ++q) {
        const std::int64_t i = q & 1 ? i1[0] : i0[0], j = q & 2 ? i1[1] : i0[1], k = q & 4 ? i1[2] : i0[2];
        std::uint32_t m = b;
        while (m < end && !patch[L.cand[m]].holds(i, j, k)) ++m;
        if (m == end) return false;
        c[q] = load(patch[L.cand[m]], i, j, k);
      }
    }
    for (double& x : c)
      if (!std::isfinite(x)) x = x > 0.0 ? nf_hi : nf_lo;
    *out = trilinear(
        [&](int x, int y, int z) __attribute__((always_inline)) { return c[x | y << 1 | z << 2]; }, f);
    return true;
  }
};
static_assert(std::is_trivially_copyable_v<AmrFieldView>);

}  // namespace tessera
