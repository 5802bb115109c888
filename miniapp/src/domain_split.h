#pragma once
/// tessera-heat --domains-per-rank N: this rank's array published as N domains (zero copy:
/// each domain's descriptor points into the solver's array), cut along the rank's longest axis
/// in uneven slabs (slab d gets about (d + 1) / (1 + 2 + ... + N) of the planes, at least one),
/// so that users see several blocks per rank work under mpirun (docs/miniapp.md).
#include <tessera/tessera.h>

#include <array>
#include <cstdint>
#include <vector>

namespace heat {

/// The most --domains-per-rank accepts.
inline constexpr std::int64_t kMaxDomainsPerRank = 1024;

/// The slabs of `whole` (the rank's field: its array with one ghost layer on every side, real
/// elements at global `offset`): n domains, each with one ghost layer on every side (its
/// neighbours' planes, or the array's own ghosts). `fields` receives their descriptors (one
/// each, the storage the domains point into). Throws std::invalid_argument when the longest
/// real extent has fewer than n planes.
std::vector<tessera_domain> split_domains(const tessera_field& whole, const std::array<std::int64_t, 3>& offset,
                                          std::int64_t n, std::vector<tessera_field>& fields);

}  // namespace heat
