#pragma once
/// tessera-heat --amr: the descriptors of this rank's domains, every level (zero copy: each
/// points into the solver's array or an AmrLevels patch).
#include "amr_levels.h"

#include <tessera/tessera.h>

#include <vector>

namespace heat {

/// Appends a domain for each patch to `domains` (level, offset, one field named like `like`,
/// float64, no ghosts), its field descriptor kept in `fields`. Pointers into `fields` stay
/// valid until it is next changed.
void append_amr_domains(const std::vector<AmrPatch>& patches, const tessera_field& like,
                        std::vector<tessera_field>& fields, std::vector<tessera_domain>& domains);

}  // namespace heat
