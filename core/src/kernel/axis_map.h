#pragma once
/// AxisMap: the kernels' view of one rectilinear axis. Its samples ("knots") are the caller's
/// vertex coordinates, or the centres of the caller's cell boundaries, read in place (never
/// copied). A world coordinate finds its segment through a uniform bin table made by prepare
/// (axis_tables.h): the bin's first segment, then a walk over the few knots inside that bin
/// (a binary search within the bin where the table was capped), so a lookup costs no search
/// over the axis. Trivially copyable; points into the caller's array and the prepared scene.
#include <tessera/host_device.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>

namespace tessera {

struct AxisMap {
  const double* coords = nullptr;      ///< the caller's coordinates; nullptr = uniform axis
  bool cell = false;                   ///< coords are n + 1 cell boundaries, knots their midpoints
  std::int64_t n = 1;                  ///< knots (samples) along the axis
  double lo = 0.0, hi = 0.0;           ///< first and last knot, world units
  const std::int64_t* bins = nullptr;  ///< nbins + 1 entries: the segment holding each bin's start
  std::int64_t nbins = 1;
  double inv_bin = 0.0;           ///< bins per world unit
  const double* walls = nullptr;  ///< macrocell c spans [walls[c], walls[c + 1]], world units

  /// Position of knot i in [0, n), world units.
  TESSERA_HOST_DEVICE double knot(std::int64_t i) const { return cell ? 0.5 * (coords[i] + coords[i + 1]) : coords[i]; }

  /// The segment s in [0, n - 2] (0 when n < 2) holding world coordinate x clamped to the
  /// knots [lo, hi], and the fraction f in [0, 1] of x along it.
  TESSERA_HOST_DEVICE void locate(double x, std::int64_t* seg, double* f) const {
    if (n < 2) {
      *seg = 0;
      *f = 0.0;
      return;
    }
    const double xc = std::clamp(x, lo, hi);
    const std::int64_t b = std::clamp<std::int64_t>(static_cast<std::int64_t>((xc - lo) * inv_bin), 0, nbins - 1);
    std::int64_t s = bins[b];
    const std::int64_t e = std::min(bins[b + 1] + 1, n - 2);  // + 1: rounding at the bin's end
    if (e - s > 8) {
      // A capped table: binary search inside the bin (knot(lo_s) <= xc holds up to rounding)
      std::int64_t lo_s = s, hi_s = e;
      while (lo_s < hi_s) {
        const std::int64_t mid = lo_s + (hi_s - lo_s + 1) / 2;
        if (knot(mid) <= xc) lo_s = mid;
        else hi_s = mid - 1;
      }
      s = lo_s;
    } else {
      while (s < e && knot(s + 1) <= xc) ++s;
    }
    while (s > 0 && knot(s) > xc) --s;  // rounding at the bin's start
    const double k0 = knot(s), k1 = knot(s + 1);
    *seg = s;
    *f = std::clamp((xc - k0) / (k1 - k0), 0.0, 1.0);
  }

  /// Width of the segment holding x (world units; 0 when n < 2).
  TESSERA_HOST_DEVICE double local_spacing(double x) const {
    if (n < 2) return 0.0;
    std::int64_t s;
    double f;
    locate(x, &s, &f);
    return knot(s + 1) - knot(s);
  }
};
static_assert(std::is_trivially_copyable_v<AxisMap>);

}  // namespace tessera
