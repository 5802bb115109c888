// MpiParallelContext, field replica: every rank's box of the field gathered into one
// shared-memory replica per node (assemble(); parallel_context_mpi.h says how).
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"

#include <climits>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::insitu {
namespace {

using detail::check;

std::string box_text(const std::int64_t offset[3], const std::int64_t dims[3]) {
  std::string s = "[";
  for (int a = 0; a < 3; ++a)
    s += (a ? ", " : "") + std::to_string(offset[a]) + ".." + std::to_string(offset[a] + dims[a]);
  return s + ")";
}

std::string dims_text(const std::int64_t dims[3]) {
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
}

/// Every rank's box, the first 8 by name: "rank 0 [0..4, 0..8, 0..8), rank 1 ...".
template <class Box>
std::string boxes_text(const std::vector<Box>& boxes) {
  constexpr std::size_t kShown = 8;
  std::string s;
  for (std::size_t r = 0; r < boxes.size() && r < kShown; ++r)
    s += (r ? ", rank " : "rank ") + std::to_string(r) + " " + box_text(boxes[r].offset, boxes[r].dims);
  if (boxes.size() > kShown) s += " and " + std::to_string(boxes.size() - kShown) + " more ranks";
  return s;
}

/// Copies a strided view into its box of the C-order replica: one copy, no staging buffer.
template <std::size_t E>
void copy_box_typed(const FieldView& v, unsigned char* replica, const std::int64_t global[3],
                    const std::int64_t offset[3]) {
  const auto* src0 = static_cast<const unsigned char*>(v.data);
  const std::int64_t s0 = v.byte_strides[0];
  for (std::int64_t k = 0; k < v.dims[2]; ++k)
    for (std::int64_t j = 0; j < v.dims[1]; ++j) {
      const unsigned char* src = src0 + j * v.byte_strides[1] + k * v.byte_strides[2];
      unsigned char* dst = replica + E * (((offset[2] + k) * global[1] + offset[1] + j) * global[0] + offset[0]);
      if (s0 == static_cast<std::int64_t>(E)) {
        std::memcpy(dst, src, E * static_cast<std::size_t>(v.dims[0]));
      } else {
        for (std::int64_t i = 0; i < v.dims[0]; ++i) std::memcpy(dst + E * i, src + i * s0, E);
      }
    }
}

void copy_box(const FieldView& v, void* replica, const std::int64_t global[3], const std::int64_t offset[3]) {
  auto* dst = static_cast<unsigned char*>(replica);
  switch (dtype_size(v.dtype)) {
    case 1: copy_box_typed<1>(v, dst, global, offset); break;
    case 2: copy_box_typed<2>(v, dst, global, offset); break;
    case 4: copy_box_typed<4>(v, dst, global, offset); break;
    default: copy_box_typed<8>(v, dst, global, offset); break;
  }
}

}  // namespace

void MpiParallelContext::free_replica() {
  if (m_replica_win == MPI_WIN_NULL) return;
  MPI_Win_unlock_all(m_replica_win);
  MPI_Win_free(&m_replica_win);
  m_replica = nullptr;
  m_replica_bytes = 0;
}

void MpiParallelContext::ensure_replica(std::uint64_t bytes) {
  if (m_replica_win != MPI_WIN_NULL && bytes == m_replica_bytes) return;
  free_replica();
  // The leader allocates the whole replica; the others map the leader's segment.
  const MPI_Aint mine = m_node_rank == 0 ? static_cast<MPI_Aint>(bytes) : 0;
  void* base = nullptr;
  check(MPI_Win_allocate_shared(mine, 1, MPI_INFO_NULL, m_node, &base, &m_replica_win), "MPI_Win_allocate_shared");
  MPI_Win_set_errhandler(m_replica_win, MPI_ERRORS_RETURN);
  MPI_Aint size = 0;
  int disp_unit = 0;
  check(MPI_Win_shared_query(m_replica_win, 0, &size, &disp_unit, &m_replica), "MPI_Win_shared_query");
  m_replica_bytes = bytes;
  check(MPI_Win_lock_all(MPI_MODE_NOCHECK, m_replica_win), "MPI_Win_lock_all");
}

void MpiParallelContext::exchange_boxes(const FieldView& local, const std::vector<RankBox>& boxes) {
  const RankBox& me = boxes[m_rank];
  detail::TypeList keep;
  std::vector<int> send_counts(m_size, 0), recv_counts(m_size, 0), zero(m_size, 0);
  std::vector<MPI_Datatype> send_types(m_size, MPI_BYTE), recv_types(m_size, MPI_BYTE);
  MPI_Request request = MPI_REQUEST_NULL;
  const std::uint64_t box_bytes = static_cast<std::uint64_t>(local.vertex_count()) * dtype_size(local.dtype);

  // Other nodes: my view, read in place, to each other node's leader, straight into the box
  // that the leader's receive type describes.
  if (m_node_count > 1) {
    const MPI_Datatype view = detail::strided_view_type(local, keep);
    for (int d = 0; d < m_size; ++d)
      if (m_leader_of[d] == d && d != m_leader_of[m_rank]) {
        send_counts[d] = 1;
        send_types[d] = view;
        m_report.assemble_bytes += box_bytes;
      }
    if (m_node_rank == 0)
      for (int s = 0; s < m_size; ++s)
        if (m_leader_of[s] != m_rank) {
          recv_counts[s] = 1;
          recv_types[s] = detail::replica_box_type(local.dtype, boxes[s].global, boxes[s].offset, boxes[s].dims, keep);
        }
    check(MPI_Ialltoallw(local.data, send_counts.data(), zero.data(), send_types.data(), m_replica, recv_counts.data(),
                         zero.data(), recv_types.data(), m_comm, &request),
          "MPI_Ialltoallw");
  }

  // This node: each rank writes its own box into the shared replica, all ranks at once.
  copy_box(local, m_replica, me.global, me.offset);
  m_report.assemble_bytes += box_bytes;

  if (request != MPI_REQUEST_NULL) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "MPI_Wait");
}

std::vector<MpiParallelContext::RankBox> MpiParallelContext::check_boxes(const FieldView& local,
                                                                         const GlobalPlacement& where) {
  // Everyone learns everyone's box; the checks below then fail alike on every rank.
  RankBox mine{};
  std::string view_error;
  try {
    local.validate("field");
  } catch (const std::exception& e) {
    view_error = e.what();
  }
  for (int a = 0; a < 3; ++a) {
    mine.offset[a] = where.offset[a];
    mine.dims[a] = local.dims[a];
    mine.global[a] = where.global_dims[a];
  }
  mine.dtype = static_cast<std::int64_t>(local.dtype);
  mine.view_ok = view_error.empty() ? 1 : 0;
  constexpr int kWords = sizeof(RankBox) / sizeof(std::int64_t);
  std::vector<RankBox> boxes(m_size);
  check(MPI_Allgather(&mine, kWords, MPI_INT64_T, boxes.data(), kWords, MPI_INT64_T, m_comm), "MPI_Allgather");

  // Check the decomposition: one dtype, one global grid, disjoint boxes covering it.
  const RankBox& first = boxes[0];
  std::int64_t covered = 0;
  for (int r = 0; r < m_size; ++r) {
    const RankBox& b = boxes[r];
    const std::string who = "rank " + std::to_string(r);
    if (!b.view_ok) throw LayoutError(r == m_rank ? view_error : who + " published an invalid field view");
    if (b.dtype != first.dtype)
      throw LayoutError("ranks publish different dtypes: rank 0 " +
                        std::string(dtype_name(static_cast<DType>(first.dtype))) + ", " + who + " " +
                        dtype_name(static_cast<DType>(b.dtype)));
    for (int a = 0; a < 3; ++a) {
      if (b.global[a] != first.global[a])
        throw LayoutError("ranks disagree on global_dims: rank 0 has " + dims_text(first.global) + ", " + who +
                          " has " + dims_text(b.global));
      if (b.global[a] < 1 || b.global[a] > INT_MAX)
        throw LayoutError("global_dims must be in [1, " + std::to_string(INT_MAX) + "]");
      if (b.offset[a] < 0 || b.dims[a] < 1 || b.offset[a] + b.dims[a] > b.global[a])
        throw LayoutError(who + "'s real vertices " + box_text(b.offset, b.dims) + " leave the global grid");
    }
    covered += b.dims[0] * b.dims[1] * b.dims[2];
    for (int q = 0; q < r; ++q) {
      const RankBox& o = boxes[q];
      bool overlap = true;
      for (int a = 0; a < 3; ++a)
        overlap = overlap && b.offset[a] < o.offset[a] + o.dims[a] && o.offset[a] < b.offset[a] + b.dims[a];
      if (overlap)
        throw LayoutError("rank " + std::to_string(q) + "'s real vertices " + box_text(o.offset, o.dims) + " overlap " +
                          who + "'s " + box_text(b.offset, b.dims) +
                          " (declare shared vertices as ghosts on all but one rank)");
    }
  }
  const std::int64_t total = first.global[0] * first.global[1] * first.global[2];
  if (covered != total)
    throw LayoutError("the ranks' real vertices cover " + std::to_string(covered) + " of the " + std::to_string(total) +
                      " global vertices " + dims_text(first.global) + " (real vertices: " + boxes_text(boxes) + ")");
  return boxes;
}

FieldView MpiParallelContext::assemble(const FieldView& local, const GlobalPlacement& where) {
  m_report.assemble_bytes = 0;
  if (m_size == 1) {
    local.validate("field");
    for (int a = 0; a < 3; ++a)
      if (where.offset[a] != 0 || local.dims[a] != where.global_dims[a])
        throw LayoutError("one rank must hold the whole grid: its real vertices " + box_text(where.offset, local.dims) +
                          " do not cover global dims " + std::to_string(where.global_dims[0]) + "x" +
                          std::to_string(where.global_dims[1]) + "x" + std::to_string(where.global_dims[2]));
    return local;  // zero copy
  }

  end_distribution();
  const std::vector<RankBox> boxes = check_boxes(local, where);
  const RankBox& first = boxes[0];
  const std::int64_t total = first.global[0] * first.global[1] * first.global[2];

  // Nobody on this node may still be reading the previous replica while it is overwritten.
  ensure_replica(static_cast<std::uint64_t>(total) * dtype_size(local.dtype));
  check(MPI_Barrier(m_node), "MPI_Barrier");
  exchange_boxes(local, boxes);
  // Publish the node's writes to every rank of the node.
  MPI_Win_sync(m_replica_win);
  check(MPI_Barrier(m_node), "MPI_Barrier");
  MPI_Win_sync(m_replica_win);
  return FieldView::contiguous(m_replica, local.dtype, first.global[0], first.global[1], first.global[2]);
}

}  // namespace tessera::insitu
