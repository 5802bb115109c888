#pragma once
/// A render of `field: {magnitude: [a, b, c]}` (config::RenderSpec::magnitude): the three
/// components, each bound as a field of its own (field_binding.h, domain_binding.h), made one
/// scalar field whose value is magnitude() of theirs (magnitude_field.h).
///
/// - One rank holding the whole grid in one block: the magnitude is read in place, per lookup
///   (`in_place`); nothing is copied.
/// - Otherwise (several domains, several ranks, levels, distributed mode): Tessera copies into
///   a replica (or bricks) anyway, so each block's magnitudes are staged first, once per call,
///   as a dense float64 array (8 bytes per element of this rank's blocks, counted against the
///   memory limit), and everything downstream reads a float64 field.
#include "data/field_binding.h"

#include <tessera/magnitude_field.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tessera::insitu {

struct VectorField {
  FieldBinding binding;                     ///< the field as the render reads it
  std::optional<MagnitudeField> in_place;   ///< one rank, one whole block: read in place
  std::vector<std::vector<double>> staged;  ///< otherwise: per block, its magnitudes
  std::uint64_t staged_bytes = 0;           ///< bytes of `staged`
};

/// The three components' bindings (same mesh, same association, same blocks: else
/// std::invalid_argument naming the components and what differs) combined. `names`: the
/// components' names, for messages. `one_rank`: the communicator has one rank. Staging first
/// checks that its bytes are within `limit_bytes` (the memory limit, `limit_text` its words):
/// std::runtime_error naming both otherwise, before anything is allocated.
VectorField combine_components(const FieldBinding (&components)[3], const std::string (&names)[3], bool one_rank,
                               std::uint64_t limit_bytes, const std::string& limit_text);

}  // namespace tessera::insitu
