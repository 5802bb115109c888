// MpiParallelContext, refinement levels in replicated mode: every rank's boxes checked as one
// hierarchy, every patch copied into one replica per node (parallel_context.h assemble_amr).
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"

#include "amr_layout.h"
#include "block_ops.h"

#include <vector>

namespace tessera::insitu {

using detail::check;

AmrLayout MpiParallelContext::amr_layout(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc) {
  if (m_size == 1) return amr_layout_one_rank(blocks, meta, assoc);  // no MPI call
  const std::vector<FieldBlock> ordered = in_domain_order(blocks);
  std::vector<int> counts;
  std::vector<BlockRecord> all = gather_boxes(ordered, meta.dims, meta.dtype, levels_word(meta), &counts);
  return check_amr_layout(std::move(all), std::move(counts), meta, assoc);
}

std::vector<AmrPatch> MpiParallelContext::assemble_amr(std::span<const FieldBlock> blocks, const AmrLayout& layout) {
  m_report.assemble_bytes = 0;
  const std::vector<FieldBlock> ordered = in_domain_order(blocks);
  if (m_size == 1) return patches_in_place(ordered, layout);  // zero copy

  end_distribution();
  // Nobody on this node may still be reading the previous replica while it is overwritten
  ensure_replica(layout.patch_bytes());
  check(MPI_Barrier(m_node), "MPI_Barrier");
  exchange_patches(ordered, layout);
  // Publish the node's writes to every rank of the node
  MPI_Win_sync(m_replica_win);
  check(MPI_Barrier(m_node), "MPI_Barrier");
  MPI_Win_sync(m_replica_win);
  return patches_in_replica(m_replica, layout);
}

void MpiParallelContext::exchange_patches(std::span<const FieldBlock> ordered, const AmrLayout& layout) {
  const DType dtype = layout.meta.dtype;
  const std::vector<std::uint64_t> at = layout.replica_offsets();
  std::size_t mine_first = 0;  // index of this rank's first box in the layout
  for (int r = 0; r < m_rank; ++r) mine_first += static_cast<std::size_t>(layout.counts[r]);
  std::uint64_t my_bytes = 0;
  for (const FieldBlock& b : ordered) my_bytes += static_cast<std::uint64_t>(b.view.vertex_count()) * dtype_size(dtype);
  auto* replica = static_cast<unsigned char*>(m_replica);

  // Other nodes: my patches, read in place (one struct type over their absolute addresses),
  // to each other node's leader, which receives each straight into its place in the replica
  detail::TypeList keep;
  std::vector<int> send_counts(m_size, 0), recv_counts(m_size, 0), zero(m_size, 0);
  std::vector<MPI_Datatype> send_types(m_size, MPI_BYTE), recv_types(m_size, MPI_BYTE);
  MPI_Request request = MPI_REQUEST_NULL;
  if (m_node_count > 1) {
    const MPI_Datatype mine = detail::blocks_in_place_type(ordered, keep);
    for (int d = 0; d < m_size; ++d)
      if (m_leader_of[d] == d && d != m_leader_of[m_rank] && !ordered.empty()) {
        send_counts[d] = 1;
        send_types[d] = mine;
        m_report.assemble_bytes += my_bytes;
      }
    if (m_node_rank == 0) {
      std::size_t first = 0;
      const std::int64_t origin[3] = {0, 0, 0};
      for (int s = 0; s < m_size; ++s) {
        const auto n = static_cast<std::size_t>(layout.counts[s]);
        if (m_leader_of[s] != m_rank && n > 0) {
          std::vector<int> lens(n, 1);
          std::vector<MPI_Aint> displs(n);
          std::vector<MPI_Datatype> types(n);
          for (std::size_t q = 0; q < n; ++q) {
            const BlockRecord& b = layout.boxes[first + q];
            displs[q] = static_cast<MPI_Aint>(at[first + q]);
            types[q] = detail::replica_box_type(dtype, b.dims, origin, b.dims, keep);  // the whole patch
          }
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

  // This node: each rank writes its own patches into the shared replica, all ranks at once
  const std::int64_t origin[3] = {0, 0, 0};
  for (std::size_t n = 0; n < ordered.size(); ++n)
    copy_block(ordered[n].view, replica + at[mine_first + n], ordered[n].view.dims, origin);
  m_report.assemble_bytes += my_bytes;

  if (request != MPI_REQUEST_NULL) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "MPI_Wait");
}

}  // namespace tessera::insitu
