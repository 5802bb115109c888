// MpiParallelContext, field replica: every rank's box of the field gathered into one
// shared-memory replica per node (assemble(); parallel_context_mpi.h says how).
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"

#include "data/block_ops.h"

#include <climits>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::insitu {
namespace {

using detail::check;

std::string dims_text(const std::int64_t dims[3]) {
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
}

/// What each rank tells the others first: its grid, dtype, block count and whether its
/// views are usable (all int64 so that one MPI_Allgather moves it).
struct RankHeader {
  std::int64_t global[3];
  std::int64_t dtype;
  std::int64_t view_ok;
  std::int64_t nblocks;
  std::int64_t levels;  ///< levels_word(): nlevels and ratios (1 for a single level)
};

/// "nlevels 3 (ratios 2, 4)" from a levels_word.
std::string levels_text(std::int64_t w) {
  const int n = static_cast<int>(w & 0xff);
  std::string s = "nlevels " + std::to_string(n);
  for (int l = 0; l + 1 < n && l < kMaxAmrLevels - 1; ++l)
    s += (l ? ", " : " (ratios ") + std::to_string((w >> (8 + 4 * l)) & 0xf) + (l + 2 == n ? ")" : "");
  return s;
}

/// The bytes of `count` blocks, checked to fit an MPI count.
int record_bytes(std::int64_t count) {
  const std::int64_t bytes = count * static_cast<std::int64_t>(sizeof(BlockRecord));
  if (bytes > INT_MAX)
    throw LayoutError("too many domains: " + std::to_string(count) + " over all ranks (at most " +
                      std::to_string(INT_MAX / sizeof(BlockRecord)) + ")");
  return static_cast<int>(bytes);
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

void MpiParallelContext::exchange_to_replica(std::span<const FieldBlock> blocks, const std::vector<int>& counts,
                                             DType dtype, const ReceivePlace& place,
                                             const std::function<void()>& copy_own) {
  detail::TypeList keep;
  std::vector<int> send_counts(m_size, 0), recv_counts(m_size, 0), zero(m_size, 0);
  std::vector<MPI_Datatype> send_types(m_size, MPI_BYTE), recv_types(m_size, MPI_BYTE);
  MPI_Request request = MPI_REQUEST_NULL;
  std::uint64_t my_bytes = 0;
  for (const FieldBlock& b : blocks) my_bytes += static_cast<std::uint64_t>(b.view.vertex_count()) * dtype_size(dtype);

  // Other nodes: my blocks, read in place (one struct type over their absolute addresses), to
  // each other node's leader, straight into the places that the leader's receive type describes
  if (m_node_count > 1) {
    const MPI_Datatype mine = detail::blocks_in_place_type(blocks, keep);
    for (int d = 0; d < m_size; ++d)
      if (m_leader_of[d] == d && d != m_leader_of[m_rank] && !blocks.empty()) {
        send_counts[d] = 1;
        send_types[d] = mine;
        m_report.assemble_bytes += my_bytes;
      }
    if (m_node_rank == 0) {
      std::size_t first = 0;
      for (int s = 0; s < m_size; ++s) {
        const auto n = static_cast<std::size_t>(counts[s]);
        if (m_leader_of[s] != m_rank && n > 0) {
          std::vector<int> lens(n, 1);
          std::vector<MPI_Aint> displs(n, 0);
          std::vector<MPI_Datatype> types(n);
          for (std::size_t q = 0; q < n; ++q) place(first + q, keep, &displs[q], &types[q]);
          MPI_Datatype t = MPI_DATATYPE_NULL;
          check(MPI_Type_create_struct(static_cast<int>(n), lens.data(), displs.data(), types.data(), &t),
                "MPI_Type_create_struct");
          recv_counts[s] = 1;
          recv_types[s] = keep.commit(t);
        }
        first += n;
      }
    }
    check(MPI_Ialltoallw(MPI_BOTTOM, send_counts.data(), zero.data(), send_types.data(), m_replica, recv_counts.data(),
                         zero.data(), recv_types.data(), m_comm, &request),
          "MPI_Ialltoallw");
  }

  // This node: each rank writes its own blocks into the shared replica, all ranks at once.
  copy_own();
  m_report.assemble_bytes += my_bytes;

  if (request != MPI_REQUEST_NULL) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "MPI_Wait");
}

void MpiParallelContext::exchange_boxes(std::span<const FieldBlock> blocks, const std::vector<BlockRecord>& all,
                                        const std::vector<int>& counts, DType dtype) {
  std::int64_t g[3];
  for (int a = 0; a < 3; ++a) g[a] = m_global[a];
  // Box q goes to its place in the global grid
  const auto place = [&](std::size_t q, detail::TypeList& keep, MPI_Aint* displ, MPI_Datatype* type) {
    *displ = 0;
    *type = detail::replica_box_type(dtype, g, all[q].offset, all[q].dims, keep);
  };
  exchange_to_replica(blocks, counts, dtype, place, [&] {
    for (const FieldBlock& b : blocks) copy_block(b.view, m_replica, g, b.offset);
  });
}

std::int64_t levels_word(const AmrField& meta) {
  std::int64_t w = meta.nlevels & 0xff;
  for (int l = 0; l + 1 < meta.nlevels && l < kMaxAmrLevels - 1; ++l)
    w |= static_cast<std::int64_t>(meta.ratio[l] & 0xf) << (8 + 4 * l);
  return w;
}

std::vector<BlockRecord> MpiParallelContext::check_boxes(std::span<const FieldBlock> blocks,
                                                         const std::int64_t global[3], DType dtype,
                                                         std::vector<int>* counts) {
  std::vector<BlockRecord> all = gather_boxes(blocks, global, dtype, 1, counts);
  bool legacy = true;
  for (const BlockRecord& b : all) legacy = legacy && b.domain < 0;
  check_tiling(all, m_global, legacy ? "vertices" : "elements");
  return all;
}

std::vector<BlockRecord> MpiParallelContext::gather_boxes(std::span<const FieldBlock> blocks,
                                                          const std::int64_t global[3], DType dtype,
                                                          std::int64_t levels, std::vector<int>* counts) {
  // Everyone learns everyone's blocks; the checks below then fail alike on every rank.
  RankHeader mine{};
  std::string view_error;
  for (const FieldBlock& b : blocks) {
    try {
      b.view.validate(b.domain >= 0 ? "domain " + std::to_string(b.domain) : std::string("field"));
    } catch (const std::exception& e) {
      view_error = e.what();
      break;
    }
  }
  for (int a = 0; a < 3; ++a) mine.global[a] = global[a];
  mine.dtype = static_cast<std::int64_t>(dtype);
  mine.view_ok = view_error.empty() ? 1 : 0;
  mine.nblocks = static_cast<std::int64_t>(blocks.size());
  mine.levels = levels;
  constexpr int kWords = sizeof(RankHeader) / sizeof(std::int64_t);
  std::vector<RankHeader> heads(m_size);
  check(MPI_Allgather(&mine, kWords, MPI_INT64_T, heads.data(), kWords, MPI_INT64_T, m_comm), "MPI_Allgather");

  const RankHeader& first = heads[0];
  std::int64_t total = 0;
  for (int r = 0; r < m_size; ++r) {
    const RankHeader& h = heads[r];
    const std::string who = "rank " + std::to_string(r);
    if (!h.view_ok) throw LayoutError(r == m_rank ? view_error : who + " published an invalid field view");
    if (h.dtype != first.dtype)
      throw LayoutError("ranks publish different dtypes: rank 0 " +
                        std::string(dtype_name(static_cast<DType>(first.dtype))) + ", " + who + " " +
                        dtype_name(static_cast<DType>(h.dtype)));
    for (int a = 0; a < 3; ++a)
      if (h.global[a] != first.global[a])
        throw LayoutError("ranks disagree on global_dims: rank 0 has " + dims_text(first.global) + ", " + who +
                          " has " + dims_text(h.global));
    if (h.levels != first.levels)
      throw LayoutError("ranks disagree on the refinement levels: rank 0 has " + levels_text(first.levels) + ", " +
                        who + " has " + levels_text(h.levels));
    total += h.nblocks;
  }
  // Every rank's blocks, in rank order
  std::vector<BlockRecord> own(blocks.size());
  for (std::size_t n = 0; n < blocks.size(); ++n) {
    for (int a = 0; a < 3; ++a) {
      own[n].offset[a] = blocks[n].offset[a];
      own[n].dims[a] = blocks[n].view.dims[a];
    }
    own[n].rank = m_rank;
    own[n].domain = blocks[n].domain;
    own[n].level = blocks[n].level;
  }
  record_bytes(total);
  std::vector<int> bytes(m_size), displs(m_size);
  int at = 0;
  for (int r = 0; r < m_size; ++r) {
    bytes[r] = record_bytes(heads[r].nblocks);
    displs[r] = at;
    at += bytes[r];
  }
  std::vector<BlockRecord> all(static_cast<std::size_t>(total));
  check(MPI_Allgatherv(own.data(), bytes[m_rank], MPI_BYTE, all.data(), bytes.data(), displs.data(), MPI_BYTE, m_comm),
        "MPI_Allgatherv");
  for (int a = 0; a < 3; ++a) m_global[a] = first.global[a];
  if (counts) {
    counts->resize(m_size);
    for (int r = 0; r < m_size; ++r) (*counts)[r] = static_cast<int>(heads[r].nblocks);
  }
  return all;
}

FieldView MpiParallelContext::assemble_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                              DType dtype) {
  m_report.assemble_bytes = 0;
  if (m_size == 1) return assemble_one_rank(blocks, global, dtype, m_local_replica);  // no MPI call

  end_distribution();
  std::vector<int> counts;
  const std::vector<BlockRecord> all = check_boxes(blocks, global, dtype, &counts);
  const std::int64_t total = m_global[0] * m_global[1] * m_global[2];

  // Nobody on this node may still be reading the previous replica while it is overwritten.
  ensure_replica(static_cast<std::uint64_t>(total) * dtype_size(dtype));
  check(MPI_Barrier(m_node), "MPI_Barrier");
  exchange_boxes(blocks, all, counts, dtype);
  // Publish the node's writes to every rank of the node.
  MPI_Win_sync(m_replica_win);
  check(MPI_Barrier(m_node), "MPI_Barrier");
  MPI_Win_sync(m_replica_win);
  return FieldView::contiguous(m_replica, dtype, m_global[0], m_global[1], m_global[2]);
}

}  // namespace tessera::insitu
