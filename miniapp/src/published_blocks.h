#pragma once
/// PublishedBlocks: the heat solver's array handed to tessera as several blocks (domains) per
/// rank, and optionally as cell data, without a copy (tessera-heat --domains-per-rank D,
/// --cell; docs/miniapp.md).
///
/// The rank's owned vertices are cut along its longest owned axis into D blocks of uneven
/// widths (boundaries at round(m (p / D)^1.3), each at least one plane). Each block is a
/// tessera_field over a sub-box of the solver's array: its real planes plus one ghost layer
/// on every side (the neighbouring block's planes, or the solver's own ghosts), so the blocks
/// read the same memory the solver writes, in place.
///
/// Cell data (--cell): the same values published as cells centred on the vertices (origin
/// shifted by half a spacing): the same physics, and inside the vertices' box the same
/// reconstruction; the medium then also fills the half cell beyond each wall.
#include "cart_decomposition.h"

#include <tessera/tessera.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace heat {

class PublishedBlocks {
 public:
  /// `array_dims`: the solver's local array extent with one ghost layer per side (i fastest);
  /// `spacing`: its vertex spacing. Throws std::invalid_argument when the owned extent along
  /// the cut axis is smaller than `blocks` (or blocks < 1).
  PublishedBlocks(const CartDecomposition& decomp, const Index3& array_dims, const std::array<double, 3>& spacing,
                  int blocks, bool cell);

  /// The blocks over `data` (the solver's array, valid for the call it is passed to).
  std::span<const tessera_domain> domains(const double* data);
  const tessera_mesh& mesh() const { return m_mesh; }

 private:
  struct Cut {
    std::int64_t lo, hi;  ///< owned planes [lo, hi) along the cut axis, local indices
  };
  tessera_mesh m_mesh{};
  Index3 m_array{};
  Index3 m_offset{};
  int m_axis = 2;
  std::vector<Cut> m_cuts;
  std::vector<tessera_field> m_fields;
  std::vector<tessera_domain> m_domains;
};

}  // namespace heat
