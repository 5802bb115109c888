#pragma once
/// CartDecomposition: a global grid of vertices split into blocks over a Cartesian grid of
/// MPI ranks (MPI_Dims_create + MPI_Cart_create, not periodic).
///
/// Each global vertex is owned by exactly one rank. Along each axis, n vertices over p ranks:
/// the first n % p ranks own n / p + 1 vertices, the others n / p (so every rank owns at
/// least one: n >= p is required).
#include <mpi.h>

#include <array>
#include <cstdint>

namespace heat {

using Index3 = std::array<std::int64_t, 3>;

class CartDecomposition {
 public:
  /// Collective over `comm`. Throws std::invalid_argument if an axis has fewer vertices than
  /// ranks along it.
  CartDecomposition(MPI_Comm comm, const Index3& global_dims);
  ~CartDecomposition();
  CartDecomposition(const CartDecomposition&) = delete;
  CartDecomposition& operator=(const CartDecomposition&) = delete;

  MPI_Comm comm() const { return m_cart; }  ///< the Cartesian communicator
  int rank() const { return m_rank; }
  int size() const { return m_size; }
  const std::array<int, 3>& procs() const { return m_procs; }    ///< ranks along i, j, k
  const std::array<int, 3>& coords() const { return m_coords; }  ///< this rank's position

  const Index3& global_dims() const { return m_global; }
  const Index3& offset() const { return m_offset; }  ///< global index of the first owned vertex
  const Index3& owned() const { return m_owned; }    ///< owned vertices along each axis

  /// Neighbour rank along `axis` toward lower (dir = -1) or higher (+1) indices, or
  /// MPI_PROC_NULL at the domain boundary.
  int neighbor(int axis, int dir) const { return m_neighbors[axis][dir < 0 ? 0 : 1]; }

 private:
  MPI_Comm m_cart = MPI_COMM_NULL;
  int m_rank = 0, m_size = 1;
  std::array<int, 3> m_procs{1, 1, 1}, m_coords{0, 0, 0};
  Index3 m_global{}, m_offset{}, m_owned{};
  int m_neighbors[3][2] = {};
};

}  // namespace heat
