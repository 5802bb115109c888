#include "ring_decomposition.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace heat {

RingDecomposition::RingDecomposition(MPI_Comm comm, std::int64_t columns) : m_columns(columns) {
  MPI_Comm_size(comm, &m_size);
  if (columns < m_size)
    throw std::invalid_argument("the ring has " + std::to_string(columns) + " columns for " + std::to_string(m_size) +
                                " ranks; every rank needs at least one");
  MPI_Comm_dup(comm, &m_comm);
  MPI_Comm_rank(m_comm, &m_rank);
  const std::int64_t base = columns / m_size, extra = columns % m_size;
  m_owned = base + (m_rank < extra ? 1 : 0);
  m_offset = m_rank * base + (m_rank < extra ? m_rank : extra);
}

RingDecomposition::~RingDecomposition() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized && m_comm != MPI_COMM_NULL) MPI_Comm_free(&m_comm);
}

void RingDecomposition::exchange(double* array, std::int64_t column_size) const {
  if (column_size > std::numeric_limits<int>::max())
    throw std::invalid_argument("a ring column of " + std::to_string(column_size) + " doubles is too large for MPI");
  const int n = static_cast<int>(column_size);
  double* low_ghost = array;
  double* first = array + column_size;
  double* last = array + m_owned * column_size;
  double* high_ghost = array + (m_owned + 1) * column_size;
  // First owned column to the left neighbour's high ghost; last owned to the right's low ghost
  MPI_Sendrecv(first, n, MPI_DOUBLE, left(), 0, high_ghost, n, MPI_DOUBLE, right(), 0, m_comm, MPI_STATUS_IGNORE);
  MPI_Sendrecv(last, n, MPI_DOUBLE, right(), 1, low_ghost, n, MPI_DOUBLE, left(), 1, m_comm, MPI_STATUS_IGNORE);
}

}  // namespace heat
