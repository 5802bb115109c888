#pragma once
/// HaloExchange: fills the one-vertex ghost layer of a block's array from its neighbours.
///
/// The array is the block's owned vertices plus one ghost layer on every side, C order with
/// i fastest: (owned[0]+2) x (owned[1]+2) x (owned[2]+2) doubles. Faces are MPI subarray
/// datatypes over the array itself (no packing by us). Axes are exchanged one after the
/// other, each face spanning the full ghosted extent of the other two axes, so edge and
/// corner ghosts end up filled too. At the domain boundary (MPI_PROC_NULL) nothing moves.
#include "cart_decomposition.h"

#include <cstdint>

namespace heat {

class HaloExchange {
 public:
  explicit HaloExchange(const CartDecomposition& decomp);
  ~HaloExchange();
  HaloExchange(const HaloExchange&) = delete;
  HaloExchange& operator=(const HaloExchange&) = delete;

  /// Collective over decomp.comm(): exchanges all six faces of `field`.
  void exchange(double* field) const;

  /// Bytes this rank sends per exchange (for reports).
  std::uint64_t bytes_per_exchange() const { return m_bytes; }

 private:
  const CartDecomposition& m_decomp;
  /// [axis][0] first owned layer, [1] last owned layer, [2] low ghost layer, [3] high ghost.
  MPI_Datatype m_face[3][4];
  std::uint64_t m_bytes = 0;
};

}  // namespace heat
