#pragma once
/// BrickService: the MPI side of the demand-paged field (distributed mode, docs/mpi.md). One
/// per rank, driven by the one thread that makes MPI calls while worker threads render:
///
/// - it serves: another rank's request for brick b is answered with this rank's part of b,
///   sent straight from the simulation's array (a derived datatype over its byte strides, no
///   staging copy); a block in device memory (FieldBlock::on_device) has the part packed on
///   its device and copied to a host buffer first (cuda_copy_box_to_host), kept until the
///   send completes;
/// - it fetches: bricks this rank's workers wanted (BrickCache::take_wanted) get a slot; the
///   parts that other ranks own are received straight into the slot (a subarray datatype),
///   then the brick is published (the part in this rank's first block is read in place, never
///   from a slot, unless that block is device memory: then it is copied from the device too);
/// - when the cache is full it evicts the older half of it at the next quiescent moment
///   (BrickCache::try_flush).
///
/// Messages: a request is two int64 {brick, fetch id} on kTagRequest; the reply from each
/// owner comes on kTagReply + fetch id, which the requester posted a receive for before it
/// sent the request. At most kMaxInFlight fetches are in flight per rank.
///
/// Ending (the NBX pattern): when a rank's own work is done and none of its fetches is in
/// flight it enters MPI_Ibarrier and keeps serving until the barrier completes, i.e. until no
/// rank can ask anything any more; then its sends complete. No rank waits for a rank that has
/// stopped serving.
#include <tessera/brick_cache.h>
#include <tessera/field_view.h>

#include "parallel/parallel_context.h"

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <utility>
#include <vector>

namespace tessera::insitu {

/// A block in the global grid: vertices [offset, offset + dims), held by rank `owner`.
struct BlockBox {
  std::int64_t offset[3];
  std::int64_t dims[3];
  int owner = 0;
};

/// Traffic of one BrickService (this rank), for reports and benchmarks.
struct BrickTraffic {
  std::uint64_t requests_sent = 0;      ///< request messages to owners
  std::uint64_t requests_served = 0;    ///< requests answered
  std::uint64_t bytes_received = 0;     ///< field bytes received into slots
  std::uint64_t bytes_sent = 0;         ///< field bytes sent to other ranks
  std::uint64_t bytes_from_device = 0;  ///< bytes of own device blocks copied to the host (sent or slotted)
};

class BrickService {
 public:
  static constexpr int kTagRequest = 7001;
  static constexpr int kTagReply = 8000;
  static constexpr int kMaxInFlight = 64;

  /// `boxes`: every rank's blocks, in rank order (already checked: disjoint, covering the
  /// grid); `own`: this rank's blocks, in the same order as its entries of `boxes` (the kernels
  /// read the first in place, and every brick wholly inside another; a straddling brick's
  /// parts in the others are copied into its slot, without a message). Holds references to all four. Builds an index
  /// of the blocks each brick touches (one entry per block and brick it touches), so that a
  /// request or a fetch looks only at those.
  BrickService(MPI_Comm comm, int rank, const std::vector<BlockBox>& boxes, const std::vector<FieldBlock>& own,
               BrickCache& cache);
  ~BrickService();
  BrickService(const BrickService&) = delete;
  BrickService& operator=(const BrickService&) = delete;

  /// One round: serve every pending request, start fetches for wanted bricks (waiting up to
  /// `wait` for a worker to want one when nothing else is to do), complete finished fetches
  /// and sends. Throws std::runtime_error on an MPI error or a malformed request.
  void progress(std::chrono::microseconds wait);
  /// No fetch in flight and none waiting for a slot or a fetch id.
  bool idle() const { return m_pending.empty() && m_in_flight == 0; }
  /// This rank's work is done: serves the others until every rank is done (see above).
  /// Collective. Fetches still pending are abandoned (the cache has failed) only on error.
  void drain();

  const BrickTraffic& traffic() const { return m_traffic; }

 private:
  struct Fetch {
    std::int64_t brick = -1;
    unsigned char* slot = nullptr;
    std::int64_t message[2] = {0, 0};   ///< {brick, id}, the request sent to each owner
    std::vector<MPI_Request> requests;  ///< receives from owners, then request sends
  };
  void serve_requests();
  void serve(int source, const std::int64_t message[2]);
  bool start_fetch(std::int64_t brick);
  void complete_fetches();
  void complete_sends();
  /// cuda_copy_box_to_host of `part` (of `block`, device memory) into `dst` (`bytes`), counted.
  /// A failure (a CUDA error: the array freed, the GPU disabled) leaves zeros and fails this
  /// rank's cache naming it: the replies and fills still flow as the other ranks expect, and
  /// this rank's render fails once every rank is done (no rank waits for a reply that never
  /// comes).
  void copy_device_part(unsigned char* dst, std::size_t bytes, const FieldBlock& block, const FieldView& part);
  /// The elements of `part` (brick `brick`'s part in m_boxes[n], one of this rank's device
  /// blocks) on the host, densely: copied once per service (this call's values) and kept while
  /// the kept parts stay within m_parts_cap, else copied into `spare` each time.
  const unsigned char* device_part(std::int64_t brick, std::size_t n, const FieldView& part,
                                   std::vector<unsigned char>& spare);

  MPI_Comm m_comm;
  int m_rank;
  const std::vector<BlockBox>& m_boxes;
  const std::vector<FieldBlock>& m_own;
  std::size_t m_first_own = 0;               ///< index in m_boxes of this rank's first block
  std::vector<std::int64_t> m_brick_start;   ///< per brick: where its blocks begin in m_brick_blocks
  std::vector<std::int64_t> m_brick_blocks;  ///< block indices (into m_boxes), brick by brick, in order
  BrickCache& m_cache;
  std::vector<Fetch> m_fetches;  ///< kMaxInFlight, by id; brick -1 = free
  int m_in_flight = 0;
  std::deque<std::int64_t> m_pending;  ///< taken from the cache, not yet started
  std::vector<std::int64_t> m_taken;   ///< scratch for take_wanted
  std::vector<MPI_Request> m_sends;    ///< replies in flight
  /// The host copies of device parts that replies in flight send (freed with m_sends)
  std::vector<std::vector<unsigned char>> m_send_copies;
  std::vector<unsigned char> m_part;  ///< scratch: a device part copied for a slot
  /// Device parts copied to the host, by (brick, block), kept for the call: a part asked for
  /// again (by another rank, or after an eviction) is not copied again. At most m_parts_cap
  /// bytes (the brick cache's own size, which the plan fitted in memory_limit_mb; never more
  /// than the device blocks themselves, which the staging copied whole).
  std::map<std::pair<std::int64_t, std::size_t>, std::vector<unsigned char>> m_parts;
  std::uint64_t m_parts_bytes = 0;
  std::uint64_t m_parts_cap = 0;
  BrickTraffic m_traffic;
};

}  // namespace tessera::insitu
