// MpiParallelContext, refinement levels in replicated mode: every rank's boxes checked as one
// hierarchy, every patch copied into one replica per node (parallel_context.h assemble_amr).
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"

#include "data/amr_layout.h"
#include "data/block_ops.h"

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
  auto* replica = static_cast<unsigned char*>(m_replica);
  const std::int64_t origin[3] = {0, 0, 0};
  // Patch q goes whole, dense, to its offset in the replica
  const auto place = [&](std::size_t q, detail::TypeList& keep, MPI_Aint* displ, MPI_Datatype* type) {
    const BlockRecord& b = layout.boxes[q];
    *displ = static_cast<MPI_Aint>(at[q]);
    *type = detail::replica_box_type(dtype, b.dims, origin, b.dims, keep);
  };
  exchange_to_replica(ordered, layout.counts, dtype, place, [&] {
    for (std::size_t n = 0; n < ordered.size(); ++n)
      copy_block(ordered[n].view, replica + at[mine_first + n], ordered[n].view.dims, origin);
  });
}

}  // namespace tessera::insitu
