#include "halo_exchange.h"

namespace heat {

HaloExchange::HaloExchange(const CartDecomposition& decomp) : m_decomp(decomp) {
  const Index3& n = decomp.owned();
  // MPI_ORDER_C lists the slowest axis (k) first.
  const int sizes[3] = {static_cast<int>(n[2] + 2), static_cast<int>(n[1] + 2), static_cast<int>(n[0] + 2)};
  for (int a = 0; a < 3; ++a) {
    const int c = 2 - a;  // axis a in C order
    int sub[3] = {sizes[0], sizes[1], sizes[2]};
    sub[c] = 1;
    // Layer positions along the axis, in array indices (ghost at 0, owned 1..n, ghost n+1).
    const int layer[4] = {1, static_cast<int>(n[a]), 0, static_cast<int>(n[a] + 1)};
    for (int f = 0; f < 4; ++f) {
      int start[3] = {0, 0, 0};
      start[c] = layer[f];
      MPI_Type_create_subarray(3, sizes, sub, start, MPI_ORDER_C, MPI_DOUBLE, &m_face[a][f]);
      MPI_Type_commit(&m_face[a][f]);
    }
    const std::uint64_t face = static_cast<std::uint64_t>(sub[0]) * sub[1] * sub[2] * sizeof(double);
    for (int dir : {-1, 1})
      if (decomp.neighbor(a, dir) != MPI_PROC_NULL) m_bytes += face;
  }
}

HaloExchange::~HaloExchange() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  for (auto& axis : m_face)
    for (MPI_Datatype& t : axis) MPI_Type_free(&t);
}

void HaloExchange::exchange(double* field) const {
  const MPI_Comm comm = m_decomp.comm();
  for (int a = 0; a < 3; ++a) {
    const int lo = m_decomp.neighbor(a, -1), hi = m_decomp.neighbor(a, +1);
    // Last owned layer up, low ghost layer filled from below; then the reverse.
    MPI_Sendrecv(field, 1, m_face[a][1], hi, 2 * a, field, 1, m_face[a][2], lo, 2 * a, comm, MPI_STATUS_IGNORE);
    MPI_Sendrecv(field, 1, m_face[a][0], lo, 2 * a + 1, field, 1, m_face[a][3], hi, 2 * a + 1, comm, MPI_STATUS_IGNORE);
  }
}

}  // namespace heat
