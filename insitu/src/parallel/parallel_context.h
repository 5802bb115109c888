#pragma once
/// ParallelContext: everything the adapter needs from MPI, behind one small interface, so the
/// adapter logic is the same with and without MPI.
///
/// Two implementations, chosen at build time: parallel_context_serial.cpp (no MPI; a single
/// rank) and parallel_context_mpi*.cpp (TESSERA_WITH_MPI). Every member is collective: all ranks
/// of the communicator call it in the same order. Errors throw std::runtime_error; callers must
/// first agree() on local failures so that no rank is left waiting in a collective.
#include "data/field_block.h"

#include <tessera/amr.h>
#include <tessera/brick_cache.h>
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/film.h>
#include <tessera/render.h>
#include <tessera/stats.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tessera::insitu {

struct AmrLayout;    // amr_layout.h
struct BlockRecord;  // block_layout.h

class ParallelContext {
 public:
  /// comm_f: a Fortran MPI communicator handle (MPI_Comm_c2f), or -1 for no MPI (one rank).
  /// Throws if comm_f != -1 and the build has no MPI, or if the handle is invalid.
  /// Construction in two collective steps: create() only duplicates the communicator (enough
  /// for agree(), allgather() and broadcast()); connect() then groups the ranks into nodes
  /// and sets up the shared windows. Call connect() once, after the ranks have agreed on
  /// their config and environment (rank_agreement.h), because it reads
  /// TESSERA_MPI_RANKS_PER_NODE, and ranks reading different values would split the
  /// communicator differently and hang. assemble() and render() need connect().
  static std::unique_ptr<ParallelContext> create(int comm_f);
  virtual ~ParallelContext() = default;

  /// Second construction step (see create()). Throws (alike on every rank, given agreed
  /// environments) if TESSERA_MPI_RANKS_PER_NODE is not an integer >= 0.
  virtual void connect() = 0;

  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Ranks sharing this rank's node (its memory), >= 1: the default memory limit divides the
  /// node's memory among them.
  virtual int ranks_on_node() const { return 1; }
  /// This rank's index among the ranks of its node, in [0, ranks_on_node()): picks its GPU
  /// (`tessera.cuda_device: -1`).
  virtual int rank_on_node() const { return 0; }

  /// False once communication is no longer possible (MPI finalized): close then releases
  /// without agreeing. Not collective.
  virtual bool can_communicate() const { return true; }

  /// True on every rank iff ok is true on every rank (allreduce of a flag).
  virtual bool agree(bool ok) = 0;
  /// True on every rank iff `flag` is true on some rank (allreduce of a flag).
  virtual bool any(bool flag) = 0;
  /// The smallest of every rank's `value`, on every rank (allreduce).
  virtual int min(int value) = 0;
  /// Global min and max of per-rank values (allreduce).
  virtual std::pair<double, double> range(double local_min, double local_max) = 0;
  /// Every rank's `bytes` bytes at `mine`, in rank order, into `all` (size() * bytes bytes).
  /// Every rank must pass the same `bytes`; the data travel as raw bytes.
  virtual void allgather(const void* mine, std::size_t bytes, void* all) = 0;
  /// As allgather(), but never silent while it waits: once the call has waited `warn_after`
  /// seconds (> 0; 0 = never) for the other ranks, and again each time the wait doubles, it
  /// calls on_wait(seconds waited so far) on this rank (an exception from it is ignored), then
  /// goes on waiting. Polls (MPI_Iallgather + MPI_Test, pauses of at most a millisecond) where
  /// allgather() blocks; a non-blocking collective matches only its own kind, so every rank
  /// must call this one where one does.
  virtual void allgather_waiting(const void* mine, std::size_t bytes, void* all, double warn_after,
                                 const std::function<void(double)>& on_wait) {
    (void)warn_after;
    (void)on_wait;
    allgather(mine, bytes, all);
  }
  /// Rank `root`'s `text` on every rank (other ranks' `text` is replaced). Two collectives
  /// (length, then bytes); meant for failure paths, not per call.
  virtual void broadcast(std::string& text, int root) = 0;
  /// Every rank's `mine`, in rank order, on every rank (sizes may differ). Throws
  /// std::length_error, on every rank alike, when the sum passes `max_total` bytes. This form:
  /// one allgather of the sizes, then one broadcast per rank; MPI overrides it with one
  /// MPI_Allgatherv.
  virtual std::vector<std::string> allgather_bytes(const std::string& mine, std::size_t max_total) {
    const std::uint64_t size = mine.size();
    std::vector<std::uint64_t> sizes(static_cast<std::size_t>(this->size()));
    allgather(&size, sizeof size, sizes.data());
    std::uint64_t total = 0;
    for (const std::uint64_t s : sizes) total += s;
    if (total > max_total)
      throw std::length_error("the ranks' pieces hold " + std::to_string(total) + " bytes, more than " +
                              std::to_string(max_total));
    std::vector<std::string> all(sizes.size());
    for (int r = 0; r < this->size(); ++r) {
      if (r == rank()) all[static_cast<std::size_t>(r)] = mine;
      broadcast(all[static_cast<std::size_t>(r)], r);
    }
    return all;
  }

  /// The whole field, for rendering, from each rank's view of its real vertices.
  /// One rank whose view covers the global grid: returns that view itself (zero copy).
  /// Several ranks: packs straight from the local views into one replica per node (MPI-3
  /// shared-memory window) and returns a view of it, valid until the next assemble() or the
  /// destruction of the context. All ranks must pass the same dtype and global dims; boxes
  /// that do not tile the global grid throw LayoutError.
  /// (One block: assemble_blocks with that block.)
  FieldView assemble(const FieldView& local, const GlobalPlacement& where) {
    return assemble_blocks(one_block(local, where), where.global_dims, local.dtype);
  }
  /// As assemble(), from any number of blocks per rank (zero included), of dtype `dtype`
  /// (every rank passes the same dtype and global_dims). One rank holding one block that
  /// covers the grid: that view itself (zero copy). One rank with several blocks: a replica
  /// the context owns (a copy), valid as above. The blocks of all ranks must tile the grid
  /// (checked in O(N log N) for N blocks over all ranks): else LayoutError naming the ranks
  /// and domains.
  virtual FieldView assemble_blocks(std::span<const FieldBlock> blocks, const std::int64_t global_dims[3],
                                    DType dtype) = 0;

  /// Refinement levels (amr_layout.h): every rank learns every rank's boxes (FieldBlock::level,
  /// offset, dims; one allgather as assemble_blocks makes) and checks them as one hierarchy of
  /// `meta` (dtype, level-0 dims, nlevels, ratios; check_amr_boxes), the boxes named "rank R
  /// domain D". Throws LayoutError alike on every rank (also when ranks disagree on dtype,
  /// dims or levels). Costs no copy of values: the memory plan reads the layout first.
  virtual AmrLayout amr_layout(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc) = 0;
  /// Replicated mode over refinement levels: the hierarchy's patches, readable on this rank,
  /// in the layout's (rank, domain) order; the same list on every rank up to memory
  /// addresses. One rank: the views of its blocks themselves (zero copy). Several ranks:
  /// every patch copied into one replica per node (MPI-3 shared window, as assemble_blocks;
  /// other nodes' patches received by one alltoallw straight into place), each dense C
  /// order, valid until the next assemble or the destruction of the context. `blocks`: this
  /// rank's blocks as passed to amr_layout(), which made `layout`.
  virtual std::vector<AmrPatch> assemble_amr(std::span<const FieldBlock> blocks, const AmrLayout& layout) = 0;

  /// Distributed mode (docs/mpi.md): the summary of the global field for macrocell edge `edge`
  /// from every rank's partial summary of its own block, combined by reductions (bit-identical
  /// to a summary of the whole field). Checks the boxes as assemble() does first.
  std::shared_ptr<const FieldSummary> summarize(const FieldView& local, const GlobalPlacement& where, int edge) {
    return summarize_blocks(one_block(local, where), where.global_dims, local.dtype, edge);
  }
  /// As summarize(), from any number of blocks per rank: the partial summaries of every block
  /// of every rank combined (exact in any order, so bit-identical to the whole field's). The
  /// summary's recorded layout is the first block's (the one distribute_blocks reads in place).
  virtual std::shared_ptr<const FieldSummary> summarize_blocks(std::span<const FieldBlock> blocks,
                                                               const std::int64_t global_dims[3], DType dtype,
                                                               int edge) = 0;

  /// Distributed mode: the field as this rank renders it without a replica: its own block read
  /// in place, every other vertex fetched from its owners brick by brick (bricks of 2^shift
  /// vertices) into a cache of `capacity` slots that the context owns (kept while the grid,
  /// dtype, shift and capacity are unchanged). Checks the boxes as assemble() does. Kernels may
  /// read the paged field only inside serve_while().
  PagedField distribute(const FieldView& local, const GlobalPlacement& where, int shift, std::size_t capacity) {
    return distribute_blocks(one_block(local, where), where.global_dims, local.dtype, shift, capacity);
  }
  /// As distribute(), from any number of blocks per rank. Every block of this rank is read in
  /// place by the kernels: the FIRST (callers put the largest first) vertex by vertex, each
  /// brick wholly inside another one through the cache's in-place table (one table load, no
  /// search: BrickCache::set_in_place). Only bricks that straddle blocks or ranks use slots;
  /// their parts in this rank's blocks (but the first) are copied into the slot by this
  /// rank's brick service (no message).
  /// A brick may span blocks of several ranks: each owner sends its parts.
  virtual PagedField distribute_blocks(std::span<const FieldBlock> blocks, const std::int64_t global_dims[3],
                                       DType dtype, int shift, std::size_t capacity) = 0;

  /// Distributed mode over refinement levels: every rank's patches paged through one virtual
  /// grid (AmrLayout::virtual_grid(); `vblocks`: this rank's blocks in domain order placed in
  /// it, virtual_blocks(); `vrecords`: every rank's, virtual_records()), bricks of 2^shift
  /// elements in a cache of `capacity` slots, as distribute_blocks() does for one level but
  /// without its tiling check (the grid has gaps no patch fills; the hierarchy is checked by
  /// amr_layout()). The kernels read this rank's own patches in place and the others' through
  /// the returned field's cache (AmrField::cache). Collective.
  virtual PagedField distribute_amr(std::span<const FieldBlock> vblocks, std::span<const BlockRecord> vrecords,
                                    const std::int64_t vdims[3], DType dtype, int shift, std::size_t capacity) = 0;
  /// Combines every rank's summary parts (min, max, or, sum: exact in any order) into
  /// `parts` on every rank. Collective.
  virtual void reduce_parts(FieldSummary::Parts& parts) = 0;

  /// Runs fn (e.g. a prepare() that reads the field) on another thread while this one serves
  /// the other ranks' brick requests and fetches the bricks fn's kernels want, until fn has
  /// returned on every rank. Collective. Rethrows fn's exception after that. With no
  /// distribute() in effect (replicated mode) it just calls fn.
  virtual void serve_while(const std::function<void()>& fn) = 0;
  /// The bytes of this rank's device blocks (FieldBlock::on_device) copied to the host by the
  /// distribution in effect so far (other ranks' bricks, the cache's slots); 0 without one.
  virtual std::uint64_t paged_bytes_from_device() const { return 0; }

  /// Render every tile of `scene` across the ranks (tiles handed out dynamically) into `film`;
  /// afterwards rank 0's film holds the complete image, others hold only their tiles. `stats`
  /// are summed over ranks on rank 0. Bit-identical to a one-rank render.
  virtual void render(const PreparedScene& scene, Film& film, RenderStats& stats) = 0;

  /// Bytes moved between ranks by the last assemble() + render() (for benchmarks).
  virtual std::uint64_t bytes_moved() const = 0;

 private:
  struct OneBlock {
    FieldBlock block;
    operator std::span<const FieldBlock>() const { return {&block, 1}; }
  };
  static OneBlock one_block(const FieldView& local, const GlobalPlacement& where) {
    OneBlock b;
    b.block.view = local;
    for (int a = 0; a < 3; ++a) b.block.offset[a] = where.offset[a];
    return b;
  }
};

}  // namespace tessera::insitu
