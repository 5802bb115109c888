#pragma once
/// MpiParallelContext: the MPI implementation of ParallelContext (parallel_context.h), one
/// file per job: setup, field replica, tile scheduler, film, statistics (named below).
///
/// Field assembly: every rank needs the whole field to trace rays through it. The field is
/// assembled into ONE replica per node, in an MPI-3 shared-memory window (the node leader
/// allocates it, the other ranks of the node map the same memory):
///   - each rank copies its own strided view straight into its box of its node's replica;
///   - each rank sends the same view, described by an MPI derived datatype over its byte
///     strides (no packing copy by us), to the leader of every other node, which receives it
///     straight into the matching sub-box of its replica (MPI_Ialltoallw, subarray types).
/// The replica is contiguous C order (i fastest) in the dtype of the local views; the window
/// is kept across calls while the size is unchanged.
///
/// Rendering: tiles are handed out dynamically from a shared counter on rank 0, advanced with
/// MPI_Fetch_and_op (MPI-3 passive-target RMA), a few tiles per grab, so that ranks finish
/// together however unevenly the image costs. Each rank renders its grabs with
/// tessera::render_tiles into its own Film; rank 0 then receives every other rank's tile
/// pixels (raw PixelSums bytes, received straight into place with indexed datatypes). Every
/// pixel's samples come from one render_tiles call and RNG streams depend only on (seed,
/// frame, pixel, sample index), so the image is bit-identical for any rank or thread count.
///
/// Thread level: all MPI calls are made by the thread that calls the context
/// (MPI_THREAD_FUNNELED suffices). Passive-target RMA on rank 0's counter relies on the MPI
/// library progressing it while rank 0 renders; within a node Open MPI's osc/sm does this in
/// hardware (shared-memory atomics).
#include "data/block_layout.h"
#include "mpi/brick_service.h"
#include "mpi/mpi_datatypes.h"
#include "parallel/parallel_context.h"

#include <mpi.h>

#include <climits>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace tessera::insitu {

/// One word for the ranks to compare: nlevels (8 bits) and each ratio (4 bits).
std::int64_t levels_word(const AmrField& meta);

/// How one MPI_Allgatherv moves every rank's piece (MpiParallelContext::allgather_bytes): each
/// piece's bytes and where it lands among the gathered bytes, as MPI's int counts.
struct AllgathervPlan {
  std::vector<int> counts;  ///< bytes of each rank's piece, in rank order
  std::vector<int> displs;  ///< offset of each rank's piece in the gathered bytes
  std::size_t total = 0;    ///< the sum of counts
};
/// The plan for pieces of `sizes` bytes (every rank's, in rank order: the same list on every
/// rank, so what this throws is thrown alike on every rank). Throws std::length_error when the
/// total passes `max_total` (the message of ParallelContext::allgather_bytes) or `int_limit`
/// bytes (INT_MAX: MPI counts and displacements are int; tests pass a smaller limit).
AllgathervPlan allgatherv_plan(std::span<const std::uint64_t> sizes, std::size_t max_total,
                               std::uint64_t int_limit = INT_MAX);

/// Per-rank figures of the last assemble() / render(), for benchmarks and tests.
struct MpiRenderReport {
  double render_seconds = 0.0;      ///< this rank: wall time in its grab-and-render loop
  double render_cpu_seconds = 0.0;  ///< this rank: process CPU time in that loop (all its
                                    ///< threads; unaffected by other processes on the cores)
  int tiles = 0;                    ///< tiles this rank rendered
  int grabs = 0;                    ///< fetch-and-add calls that returned work
  int chunk = 0;                    ///< tiles per grab
  /// Bytes this rank moved toward other ranks: its box written into the node's shared
  /// replica plus its box sent to each other node's leader.
  std::uint64_t assemble_bytes = 0;
  /// Bytes this rank sent while rendering: its tile list and tile pixels (to rank 0), or, on
  /// rank 0, the film broadcast when continuing a progressive render. Summed over ranks: the
  /// bytes one render moves.
  std::uint64_t render_bytes = 0;
  /// Distributed mode, since the last distribute(): this rank's brick traffic and cache
  BrickTraffic bricks;
  BrickCacheStats cache;
  std::uint64_t cache_bytes = 0;  ///< the cache's allocation (directory, states, slot pool)
};

class MpiParallelContext final : public ParallelContext {
 public:
  /// Context over a duplicate of `comm` (MPI must be initialised), connected at once.
  /// `ranks_per_node` > 0 groups consecutive ranks into pretend nodes of that size (for
  /// testing the inter-node path on one machine; they must still share memory); 0 groups
  /// ranks by real shared-memory node. Collective over `comm`.
  MpiParallelContext(MPI_Comm comm, int ranks_per_node);
  /// Context over a duplicate of `comm`, not yet connected: agree(), range(), allgather()
  /// and broadcast() work; connect() must follow before assemble() or render().
  /// Collective over `comm` (MPI_Comm_dup only).
  explicit MpiParallelContext(MPI_Comm comm);
  /// One rank, no MPI: behaves like the serial context.
  MpiParallelContext();
  ~MpiParallelContext() override;
  MpiParallelContext(const MpiParallelContext&) = delete;
  MpiParallelContext& operator=(const MpiParallelContext&) = delete;

  int rank() const override { return m_rank; }
  int size() const override { return m_size; }
  /// Groups the ranks by TESSERA_MPI_RANKS_PER_NODE (see the two-argument constructor).
  void connect() override;
  int ranks_on_node() const override { return m_node_size; }
  int rank_on_node() const override { return m_node_rank; }
  bool can_communicate() const override;
  bool agree(bool ok) override;
  bool any(bool flag) override;
  int min(int value) override;
  std::pair<double, double> range(double local_min, double local_max) override;
  void allgather(const void* mine, std::size_t bytes, void* all) override;
  void allgather_waiting(const void* mine, std::size_t bytes, void* all, double warn_after,
                         const std::function<void(double)>& on_wait) override;
  void broadcast(std::string& text, int root) override;
  /// One allgather of the sizes, then one MPI_Allgatherv of the bytes (the generic form: a
  /// broadcast per rank). The same pieces and the same errors, thrown alike on every rank; a
  /// total past INT_MAX bytes (one MPI_Allgatherv's int counts) is refused with
  /// std::length_error. One rank: the generic form (no MPI call).
  std::vector<std::string> allgather_bytes(const std::string& mine, std::size_t max_total) override;
  FieldView assemble_blocks(std::span<const FieldBlock> blocks, const std::int64_t global_dims[3],
                            DType dtype) override;
  std::shared_ptr<const FieldSummary> summarize_blocks(std::span<const FieldBlock> blocks,
                                                       const std::int64_t global_dims[3], DType dtype,
                                                       int edge) override;
  PagedField distribute_blocks(std::span<const FieldBlock> blocks, const std::int64_t global_dims[3], DType dtype,
                               int shift, std::size_t capacity) override;
  AmrLayout amr_layout(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc) override;
  std::vector<AmrPatch> assemble_amr(std::span<const FieldBlock> blocks, const AmrLayout& layout) override;
  PagedField distribute_amr(std::span<const FieldBlock> vblocks, std::span<const BlockRecord> vrecords,
                            const std::int64_t vdims[3], DType dtype, int shift, std::size_t capacity) override;
  void reduce_parts(FieldSummary::Parts& parts) override;
  void serve_while(const std::function<void()>& fn) override;
  std::uint64_t paged_bytes_from_device() const override { return m_report.bricks.bytes_from_device; }
  void render(const PreparedScene& scene, Film& film, RenderStats& stats) override;
  /// This rank's bytes moved by the last assemble() + render() (see MpiRenderReport; sum
  /// over ranks for the total). Not collective.
  std::uint64_t bytes_moved() const override;

  const MpiRenderReport& report() const { return m_report; }
  int node_rank() const { return m_node_rank; }
  int node_size() const { return m_node_size; }
  int node_count() const { return m_node_count; }
  /// Bytes of the replica on this rank's node (0 before the first multi-rank assemble).
  std::uint64_t replica_bytes() const { return m_replica_bytes; }

 private:
  // Setup (parallel_context_mpi_setup.cpp)
  void connect_nodes(int ranks_per_node);

  // Field replica (parallel_context_mpi_replica.cpp)
  /// Allgathers every rank's blocks (a fixed header, then the blocks themselves) and checks
  /// the decomposition (valid views, one dtype, one global grid, blocks tiling it:
  /// block_layout.h): throws LayoutError alike on every rank. In rank order, each rank's
  /// blocks in its order; `counts` (if non-null) receives the blocks per rank.
  std::vector<BlockRecord> check_boxes(std::span<const FieldBlock> blocks, const std::int64_t global[3], DType dtype,
                                       std::vector<int>* counts = nullptr);
  /// check_boxes without the tiling check: the header checks (views, dtype, global dims, and
  /// `levels`, a word every rank must pass alike: levels_word()), then every rank's blocks.
  std::vector<BlockRecord> gather_boxes(std::span<const FieldBlock> blocks, const std::int64_t global[3], DType dtype,
                                        std::int64_t levels, std::vector<int>* counts);
  void ensure_replica(std::uint64_t bytes);
  void free_replica();
  void exchange_boxes(std::span<const FieldBlock> blocks, const std::vector<BlockRecord>& all,
                      const std::vector<int>& counts, DType dtype);
  /// Where box q (every rank's boxes in rank order) lands in the replica: a displacement from
  /// the replica's start and a receive type (made through `keep`).
  using ReceivePlace = std::function<void(std::size_t q, detail::TypeList& keep, MPI_Aint* displ, MPI_Datatype* type)>;
  /// The replica's exchange, of one level's boxes or of every patch: this rank's `blocks`
  /// (read in place) to every other node's leader in one MPI_Ialltoallw, each leader receiving
  /// other nodes' boxes where `place` says, while `copy_own` writes this rank's blocks into
  /// its own node's replica. `counts`: boxes per rank.
  void exchange_to_replica(std::span<const FieldBlock> blocks, const std::vector<int>& counts, DType dtype,
                           const ReceivePlace& place, const std::function<void()>& copy_own);

  // Refinement levels, replicated (parallel_context_mpi_amr.cpp)
  /// Copies this rank's patches (`ordered`: its blocks in domain order) into its node's
  /// replica and sends them to every other node's leader, which receives them in place.
  void exchange_patches(std::span<const FieldBlock> ordered, const AmrLayout& layout);

  // Tile scheduler (parallel_context_mpi_tiles.cpp): render() with more than one rank is
  // share_film, render_grabbed_tiles, gather_film, reduce_stats, in that order on every rank.
  void render_multi(const PreparedScene& scene, Film& film, RenderStats& stats);
  /// Renders tiles grabbed from the shared counter until none is left, into `film` and
  /// `local`; returns the tiles this rank rendered. Ends in an agreement: throws on every
  /// rank alike if any rank failed or passed the deadline.
  std::vector<int> render_grabbed_tiles(const PreparedScene& scene, Film& film, RenderStats& local);

  // Distributed mode (parallel_context_mpi_paged.cpp)
  /// Runs fn on another thread while this thread serves and fetches bricks (no drain).
  void serve_during(const std::function<void()>& fn);
  /// This rank's work is done: serves until every rank's is (BrickService::drain), then
  /// throws std::runtime_error if the drain or the cache failed. Collective.
  void finish_serving();
  /// Ends distributed mode (assemble() was called): frees the service and the cache.
  void end_distribution();
  /// distribute_blocks / distribute_amr once every rank's boxes (`all`, rank order, the
  /// blocks of this rank in `blocks`' order) are known and checked.
  PagedField distribute_records(std::span<const FieldBlock> blocks, std::span<const BlockRecord> all,
                                const std::int64_t global[3], DType dtype, int shift, std::size_t capacity);

  // Film (parallel_context_mpi_film.cpp)
  /// Checks that the ranks prepared the same image and gives every rank rank 0's starting
  /// film (empty, or its samples so far).
  void share_film(const PreparedScene& scene, Film& film, MPI_Datatype pixel);
  /// Rank 0 receives the pixels of every other rank's tiles (`mine` on each rank) into `film`.
  void gather_film(const std::vector<Tile>& tiles, const std::vector<int>& mine, int width, MPI_Datatype pixel,
                   Film& film);

  // Statistics (parallel_context_mpi_stats.cpp)
  /// Rank 0: adds the counters of all ranks to `stats` (threads: the total over ranks; wall
  /// time: the slowest rank's). Other ranks add their own.
  void reduce_stats(const RenderStats& local, RenderStats& stats);

  bool m_mpi = false;
  bool m_connected = false;
  MPI_Comm m_comm = MPI_COMM_NULL;  ///< duplicate of the user's communicator
  MPI_Comm m_node = MPI_COMM_NULL;  ///< ranks sharing this node's replica
  int m_rank = 0, m_size = 1;
  int m_node_rank = 0, m_node_size = 1, m_node_count = 1;
  std::vector<int> m_leader_of;  ///< per rank of m_comm: its node leader's rank

  std::int64_t m_global[3] = {0, 0, 0};
  std::vector<unsigned char>
      m_local_replica;  ///< one rank with several domains: their copy  ///< global dims of the last checked decomposition
  MPI_Win m_replica_win = MPI_WIN_NULL;
  void* m_replica = nullptr;
  std::uint64_t m_replica_bytes = 0;

  MPI_Win m_counter_win = MPI_WIN_NULL;
  std::int64_t* m_counter = nullptr;  ///< rank 0: the next tile to hand out

  // Distributed mode: this rank's view and every rank's block, the cache and its server;
  // m_service is non-null between distribute() and the next assemble()
  std::vector<FieldBlock> m_paged_blocks;  ///< this rank's blocks (the first is read in place)
  std::vector<BlockBox> m_blocks;          ///< every rank's blocks, in rank order
  std::unique_ptr<BrickCache> m_cache;
  std::unique_ptr<BrickService> m_service;

  MpiRenderReport m_report;
};

}  // namespace tessera::insitu
