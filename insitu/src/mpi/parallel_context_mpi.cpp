// MpiParallelContext: destruction and the small collectives. The other jobs have files of
// their own: construction and byte collectives (parallel_context_mpi_setup.cpp), the field
// replica (_replica.cpp), the tile scheduler (_tiles.cpp), the film shared and gathered
// (_film.cpp) and the statistics reduced (_stats.cpp); MPI datatypes in mpi_datatypes.h.
#include "mpi/parallel_context_mpi.h"

#include "mpi/mpi_check.h"

namespace tessera::insitu {

using detail::check;

MpiParallelContext::~MpiParallelContext() {
  if (!m_mpi) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;  // too late to free anything; the process is ending
  free_replica();
  if (m_counter_win != MPI_WIN_NULL) {
    MPI_Win_unlock_all(m_counter_win);
    MPI_Win_free(&m_counter_win);
  }
  if (m_node != MPI_COMM_NULL) MPI_Comm_free(&m_node);
  if (m_comm != MPI_COMM_NULL) MPI_Comm_free(&m_comm);
}

// ---------------------------------------------------------------------------------------
// Small collectives

bool MpiParallelContext::can_communicate() const {
  if (!m_mpi) return false;
  int finalized = 0;
  MPI_Finalized(&finalized);
  return finalized == 0;
}

bool MpiParallelContext::agree(bool ok) {
  if (m_size == 1) return ok;
  int local = ok ? 1 : 0, all = 0;
  check(MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LAND, m_comm), "MPI_Allreduce");
  return all != 0;
}

bool MpiParallelContext::any(bool flag) {
  if (m_size == 1) return flag;
  int local = flag ? 1 : 0, all = 0;
  check(MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LOR, m_comm), "MPI_Allreduce");
  return all != 0;
}

int MpiParallelContext::min(int value) {
  if (m_size == 1) return value;
  int all = value;
  check(MPI_Allreduce(&value, &all, 1, MPI_INT, MPI_MIN, m_comm), "MPI_Allreduce");
  return all;
}

std::pair<double, double> MpiParallelContext::range(double local_min, double local_max) {
  if (m_size == 1) return {local_min, local_max};
  const double local[2] = {local_min, -local_max};
  double global[2];
  check(MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, m_comm), "MPI_Allreduce");
  return {global[0], -global[1]};
}

std::uint64_t MpiParallelContext::bytes_moved() const { return m_report.assemble_bytes + m_report.render_bytes; }

}  // namespace tessera::insitu
