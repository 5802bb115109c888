#pragma once
/// RingDecomposition: the columns of a periodic axis (the shell's angle, tessera-heat-shell)
/// split over the MPI ranks of a communicator, each rank's neighbours on the ring, and the
/// exchange of one ghost column per side.
///
/// n columns over p ranks: the first n % p ranks own n / p + 1 consecutive columns, the others
/// n / p (n >= p is required, so every rank owns at least one). Column n - 1's right
/// neighbour is column 0: the last rank's right neighbour is rank 0 (with one rank, itself).
///
/// A rank's array holds its owned columns plus one ghost column per side, each column
/// `column_size` contiguous doubles: ghost (local column -1), owned 0 .. owned() - 1, ghost
/// (local column owned()).
#include <mpi.h>

#include <cstdint>

namespace heat {

class RingDecomposition {
 public:
  /// Collective over `comm` (duplicates it). Throws std::invalid_argument if there are fewer
  /// columns than ranks.
  RingDecomposition(MPI_Comm comm, std::int64_t columns);
  ~RingDecomposition();
  RingDecomposition(const RingDecomposition&) = delete;
  RingDecomposition& operator=(const RingDecomposition&) = delete;

  MPI_Comm comm() const { return m_comm; }
  int rank() const { return m_rank; }
  int size() const { return m_size; }
  std::int64_t columns() const { return m_columns; }  ///< global columns
  std::int64_t offset() const { return m_offset; }    ///< global index of the first owned column
  std::int64_t owned() const { return m_owned; }      ///< owned columns, >= 1
  int left() const { return (m_rank + m_size - 1) % m_size; }
  int right() const { return (m_rank + 1) % m_size; }

  /// Collective: fills the ghost columns of `array` (owned() + 2 columns of column_size
  /// doubles, the low ghost first) from the neighbours' first and last owned columns.
  void exchange(double* array, std::int64_t column_size) const;

 private:
  MPI_Comm m_comm = MPI_COMM_NULL;
  int m_rank = 0, m_size = 1;
  std::int64_t m_columns = 0, m_offset = 0, m_owned = 0;
};

}  // namespace heat
