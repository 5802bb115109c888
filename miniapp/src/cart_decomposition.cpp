#include "cart_decomposition.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace heat {

CartDecomposition::CartDecomposition(MPI_Comm comm, const Index3& global_dims) : m_global(global_dims) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  // Ranks along each axis: as balanced as MPI_Dims_create makes them, the most ranks along
  // the longest axis (ties: the slower axis, k before j before i).
  int dims[3] = {0, 0, 0}, periods[3] = {0, 0, 0};
  MPI_Dims_create(size, 3, dims);  // non-increasing
  int by_length[3] = {2, 1, 0};
  std::stable_sort(by_length, by_length + 3, [&](int a, int b) { return global_dims[a] > global_dims[b]; });
  int cart_dims[3];
  for (int r = 0; r < 3; ++r) cart_dims[by_length[r]] = dims[r];
  for (int a = 0; a < 3; ++a)
    if (global_dims[a] < cart_dims[a])
      throw std::invalid_argument("grid axis " + std::to_string(a) + " has " + std::to_string(global_dims[a]) +
                                  " vertices for " + std::to_string(cart_dims[a]) + " ranks along it");
  MPI_Cart_create(comm, 3, cart_dims, periods, /*reorder=*/0, &m_cart);
  MPI_Comm_rank(m_cart, &m_rank);
  MPI_Comm_size(m_cart, &m_size);
  int coords[3];
  MPI_Cart_coords(m_cart, m_rank, 3, coords);
  for (int a = 0; a < 3; ++a) {
    m_procs[a] = cart_dims[a];
    m_coords[a] = coords[a];
    const std::int64_t base = global_dims[a] / m_procs[a], extra = global_dims[a] % m_procs[a];
    const std::int64_t c = m_coords[a];
    m_owned[a] = base + (c < extra ? 1 : 0);
    m_offset[a] = c * base + (c < extra ? c : extra);
    MPI_Cart_shift(m_cart, a, 1, &m_neighbors[a][0], &m_neighbors[a][1]);
  }
}

CartDecomposition::~CartDecomposition() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized && m_cart != MPI_COMM_NULL) MPI_Comm_free(&m_cart);
}

}  // namespace heat
