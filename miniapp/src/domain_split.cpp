// tessera-heat's uneven domains (domain_split.h).
#include "domain_split.h"

#include <stdexcept>
#include <string>

namespace heat {

std::vector<tessera_domain> split_domains(const tessera_field& whole, const std::array<std::int64_t, 3>& offset,
                                          std::int64_t n, std::vector<tessera_field>& fields) {
  std::int64_t real[3];
  int axis = 0;
  for (int a = 0; a < 3; ++a) {
    real[a] = whole.dims[a] - whole.ghosts_lo[a] - whole.ghosts_hi[a];
    if (real[a] > real[axis]) axis = a;
  }
  const std::int64_t planes = real[axis];
  if (n < 1 || n > planes)
    throw std::invalid_argument("--domains-per-rank " + std::to_string(n) + ": this rank has " +
                                std::to_string(planes) + " planes along its longest axis, at most that many domains");
  // Slab d: planes [cut(d), cut(d + 1)) of the real region; cut(d) = d + (planes - n) w(d) / W
  // with w(d) = 0 + 1 + ... + d (so slab d has about d + 1 shares of the spare planes)
  const std::int64_t total = n * (n + 1) / 2;
  const auto cut = [&](std::int64_t d) { return d + (planes - n) * (d * (d + 1) / 2) / total; };
  fields.assign(static_cast<std::size_t>(n), whole);
  std::vector<tessera_domain> domains(static_cast<std::size_t>(n));
  for (std::int64_t d = 0; d < n; ++d) {
    const std::int64_t lo = cut(d), hi = cut(d + 1);
    tessera_field& f = fields[static_cast<std::size_t>(d)];
    // Array element (lo + ghosts_lo - 1) along the axis: one plane below the slab (a
    // neighbour's real plane or the array's ghost) becomes the domain's low ghost
    f.data =
        static_cast<const unsigned char*>(whole.data) + (lo + whole.ghosts_lo[axis] - 1) * whole.byte_strides[axis];
    f.dims[axis] = hi - lo + 2;
    f.ghosts_lo[axis] = 1;
    f.ghosts_hi[axis] = 1;
    tessera_domain& dom = domains[static_cast<std::size_t>(d)];
    dom.level = 0;
    for (int a = 0; a < 3; ++a) dom.offset[a] = offset[a];
    dom.offset[axis] += lo;
    dom.fields = &f;
    dom.nfields = 1;
  }
  return domains;
}

}  // namespace heat
