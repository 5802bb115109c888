#pragma once
/// The trilinear blend every field lookup uses (the uniform and rectilinear grids, the
/// gradient's fast path and the refinement hierarchy's levels): one order of operations, so
/// that lookups that read the same samples by different routes agree bit for bit (a paged,
/// an AMR single-level and a plain field render the same image).

#include <tessera/host_device.h>

namespace tessera {

/// The blend of a cell's corners c(x, y, z) (each 0 or 1) with fractions f: along x, then y,
/// then z.
template <class Corner>
[[gnu::always_inline]] TESSERA_HOST_DEVICE inline double trilinear(Corner&& c, const double f[3]) {
  const double c000 = c(0, 0, 0), c100 = c(1, 0, 0), c010 = c(0, 1, 0), c110 = c(1, 1, 0);
  const double c001 = c(0, 0, 1), c101 = c(1, 0, 1), c011 = c(0, 1, 1), c111 = c(1, 1, 1);
  const double c00 = c000 + f[0] * (c100 - c000), c10 = c010 + f[0] * (c110 - c010);
  const double c01 = c001 + f[0] * (c101 - c001), c11 = c011 + f[0] * (c111 - c011);
  const double c0 = c00 + f[1] * (c10 - c00), c1 = c01 + f[1] * (c11 - c01);
  return c0 + f[2] * (c1 - c0);
}

}  // namespace tessera
