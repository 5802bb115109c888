// BrickService: serves and fetches the bricks of a demand-paged field over MPI
// (brick_service.h says how).
#include "mpi/brick_service.h"

#include "data/block_ops.h"
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"

#include <tessera/cuda_memory.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace tessera::insitu {
namespace {

using detail::check;

/// The intersection of brick box [blo, bhi) with block `b`: false if empty.
bool intersect(const std::int64_t blo[3], const std::int64_t bhi[3], const BlockBox& b, std::int64_t lo[3],
               std::int64_t hi[3]) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(blo[a], b.offset[a]);
    hi[a] = std::min(bhi[a], b.offset[a] + b.dims[a]);
    if (lo[a] >= hi[a]) return false;
  }
  return true;
}

/// The sub-view of `v` (the block at `origin`) holding global vertices [lo, hi).
FieldView sub_view(const FieldView& v, const std::int64_t origin[3], const std::int64_t lo[3],
                   const std::int64_t hi[3]) {
  FieldView s = v;
  const unsigned char* p = static_cast<const unsigned char*>(v.data);
  for (int a = 0; a < 3; ++a) {
    p += (lo[a] - origin[a]) * v.byte_strides[a];
    s.dims[a] = hi[a] - lo[a];
  }
  s.data = p;
  return s;
}

std::uint64_t box_bytes(const std::int64_t lo[3], const std::int64_t hi[3], DType t) {
  return static_cast<std::uint64_t>((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])) * dtype_size(t);
}

}  // namespace

BrickService::BrickService(MPI_Comm comm, int rank, const std::vector<BlockBox>& boxes,
                           const std::vector<FieldBlock>& own, BrickCache& cache)
    : m_comm(comm),
      m_rank(rank),
      m_boxes(boxes),
      m_own(own),
      m_cache(cache),
      m_fetches(kMaxInFlight),
      m_parts_cap(cache.allocated_bytes()) {
  while (m_first_own < m_boxes.size() && m_boxes[m_first_own].owner < m_rank) ++m_first_own;
  // The blocks each brick touches: counted, then filled (CSR), in block order
  const BrickGrid& g = m_cache.grid();
  const int s = g.shift;
  const auto bricks = static_cast<std::size_t>(g.brick_count());
  m_brick_start.assign(bricks + 1, 0);
  const auto each = [&](const BlockBox& b, auto&& fn) {
    for (std::int64_t z = b.offset[2] >> s; z <= (b.offset[2] + b.dims[2] - 1) >> s; ++z)
      for (std::int64_t y = b.offset[1] >> s; y <= (b.offset[1] + b.dims[1] - 1) >> s; ++y)
        for (std::int64_t x = b.offset[0] >> s; x <= (b.offset[0] + b.dims[0] - 1) >> s; ++x) fn(g.index(x, y, z));
  };
  for (const BlockBox& b : m_boxes) each(b, [&](std::int64_t brick) { ++m_brick_start[brick + 1]; });
  for (std::size_t n = 0; n < bricks; ++n) m_brick_start[n + 1] += m_brick_start[n];
  m_brick_blocks.resize(static_cast<std::size_t>(m_brick_start[bricks]));
  std::vector<std::int64_t> fill(m_brick_start.begin(), m_brick_start.end() - 1);
  for (std::size_t n = 0; n < m_boxes.size(); ++n)
    each(m_boxes[n], [&](std::int64_t brick) { m_brick_blocks[fill[brick]++] = static_cast<std::int64_t>(n); });
}

BrickService::~BrickService() {
  // Only after an MPI error: leave nothing pending that could write into freed memory
  for (Fetch& f : m_fetches)
    for (MPI_Request& r : f.requests)
      if (r != MPI_REQUEST_NULL) {
        MPI_Cancel(&r);
        MPI_Request_free(&r);
      }
  for (MPI_Request& r : m_sends)
    if (r != MPI_REQUEST_NULL) MPI_Request_free(&r);
}

void BrickService::progress(std::chrono::microseconds wait) {
  serve_requests();
  complete_fetches();
  complete_sends();
  // Wait for workers only when nothing is in flight here (else poll MPI again soon)
  m_taken.clear();
  m_cache.take_wanted(m_taken, m_in_flight > 0 || !m_pending.empty() ? std::chrono::microseconds(0) : wait);
  m_pending.insert(m_pending.end(), m_taken.begin(), m_taken.end());
  while (!m_pending.empty() && start_fetch(m_pending.front())) m_pending.pop_front();
}

void BrickService::serve_requests() {
  for (;;) {
    int flag = 0;
    MPI_Status st;
    check(MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, m_comm, &flag, &st), "MPI_Iprobe");
    if (!flag) return;
    std::int64_t message[2];
    check(MPI_Recv(message, 2, MPI_INT64_T, st.MPI_SOURCE, kTagRequest, m_comm, MPI_STATUS_IGNORE), "MPI_Recv");
    serve(st.MPI_SOURCE, message);
  }
}

void BrickService::serve(int source, const std::int64_t message[2]) {
  const BrickGrid& g = m_cache.grid();
  const std::int64_t brick = message[0], id = message[1];
  if (brick < 0 || brick >= g.brick_count() || id < 0 || id >= kMaxInFlight)
    throw std::runtime_error("rank " + std::to_string(source) + " asked for brick " + std::to_string(brick) +
                             " (fetch " + std::to_string(id) + "), outside the field's " +
                             std::to_string(g.brick_count()) + " bricks");
  std::int64_t blo[3], bhi[3], lo[3], hi[3];
  g.box(brick, blo, bhi);
  // This rank's blocks the brick touches, in their order: one reply each (the requester
  // posted its receives in the same order, and messages between two ranks on one tag arrive
  // in order)
  int parts = 0;
  detail::TypeList keep;  // freeing a type in use by a pending send is allowed
  for (std::int64_t at = m_brick_start[brick]; at < m_brick_start[brick + 1]; ++at) {
    const auto n = static_cast<std::size_t>(m_brick_blocks[at]);
    if (m_boxes[n].owner != m_rank || !intersect(blo, bhi, m_boxes[n], lo, hi)) continue;
    const FieldBlock& mine = m_own[n - m_first_own];
    const FieldView part = sub_view(mine.view, m_boxes[n].offset, lo, hi);
    MPI_Request r = MPI_REQUEST_NULL;
    if (mine.on_device) {
      // Device memory: the part packed on its device, sent from a host copy (same elements in
      // the same order as the strided type would send, so the receive's type matches)
      const unsigned char* copy = device_part(brick, n, part, m_send_copies.emplace_back());
      check(MPI_Isend(copy, static_cast<int>(part.vertex_count()), detail::element_type(mine.view.dtype), source,
                      kTagReply + static_cast<int>(id), m_comm, &r),
            "MPI_Isend");
    } else {
      check(MPI_Isend(part.data, 1, detail::strided_view_type(part, keep), source, kTagReply + static_cast<int>(id),
                      m_comm, &r),
            "MPI_Isend");
    }
    m_sends.push_back(r);
    m_traffic.bytes_sent += box_bytes(lo, hi, mine.view.dtype);
    ++parts;
  }
  if (parts == 0)
    throw std::runtime_error("rank " + std::to_string(source) + " asked for brick " + std::to_string(brick) +
                             ", which holds none of this rank's vertices");
  ++m_traffic.requests_served;
}

bool BrickService::start_fetch(std::int64_t brick) {
  if (m_in_flight >= kMaxInFlight) return false;
  unsigned char* slot = m_cache.reserve(brick);
  if (!slot) {
    // Every slot is taken: empty the cache once nothing is in flight and the workers rest
    if (m_in_flight > 0 || !m_cache.try_flush()) return false;
    slot = m_cache.reserve(brick);
    if (!slot) return false;
  }
  int id = 0;
  while (m_fetches[static_cast<std::size_t>(id)].brick >= 0) ++id;
  Fetch& f = m_fetches[static_cast<std::size_t>(id)];
  f.brick = brick;
  f.slot = slot;
  f.message[0] = brick;
  f.message[1] = id;
  f.requests.clear();

  const BrickGrid& g = m_cache.grid();
  const std::int64_t B = g.edge();
  std::int64_t blo[3], bhi[3], lo[3], hi[3];
  g.box(brick, blo, bhi);
  detail::TypeList keep;
  const std::int64_t slot_dims[3] = {B, B, B};
  int asked = -1;  // the last owner a request went to (an owner's blocks are consecutive)
  for (std::int64_t e = m_brick_start[brick]; e < m_brick_start[brick + 1]; ++e) {
    const auto n = static_cast<std::size_t>(m_brick_blocks[e]);
    const BlockBox& box = m_boxes[n];
    if (!intersect(blo, bhi, box, lo, hi)) continue;
    std::int64_t at[3], dims[3];
    for (int a = 0; a < 3; ++a) {
      at[a] = lo[a] - blo[a];
      dims[a] = hi[a] - lo[a];
    }
    if (box.owner == m_rank) {
      // The first own block is never read from a slot (PagedFieldView::load reads it in
      // place) unless it is device memory; the others are copied here, no message (a device
      // block's part packed on its device first)
      const FieldBlock& mine = m_own[n - m_first_own];
      if (n == m_first_own && !mine.on_device) continue;
      const FieldView part = sub_view(mine.view, box.offset, lo, hi);
      if (!mine.on_device) {
        copy_block(part, slot, slot_dims, at);
        continue;
      }
      FieldView dense = part;
      dense.data = device_part(brick, n, part, m_part);
      dense.byte_strides[0] = static_cast<std::int64_t>(dtype_size(g.dtype));
      dense.byte_strides[1] = dense.byte_strides[0] * part.dims[0];
      dense.byte_strides[2] = dense.byte_strides[1] * part.dims[1];
      copy_block(dense, slot, slot_dims, at);
      continue;
    }
    // The receive is posted before the request leaves, so the reply always has a match
    MPI_Request rr = MPI_REQUEST_NULL;
    check(MPI_Irecv(slot, 1, detail::replica_box_type(g.dtype, slot_dims, at, dims, keep), box.owner, kTagReply + id,
                    m_comm, &rr),
          "MPI_Irecv");
    f.requests.push_back(rr);
    m_traffic.bytes_received += box_bytes(lo, hi, g.dtype);
    if (asked == box.owner) continue;
    asked = box.owner;
    MPI_Request rs = MPI_REQUEST_NULL;
    check(MPI_Isend(f.message, 2, MPI_INT64_T, box.owner, kTagRequest, m_comm, &rs), "MPI_Isend");
    f.requests.push_back(rs);
    ++m_traffic.requests_sent;
  }
  if (f.requests.empty()) {  // no other owner (not asked for in practice)
    m_cache.publish(brick);
    f.brick = -1;
    return true;
  }
  ++m_in_flight;
  return true;
}

void BrickService::complete_fetches() {
  if (m_in_flight == 0) return;
  for (Fetch& f : m_fetches) {
    if (f.brick < 0) continue;
    int done = 0;
    check(MPI_Testall(static_cast<int>(f.requests.size()), f.requests.data(), &done, MPI_STATUSES_IGNORE),
          "MPI_Testall");
    if (!done) continue;
    m_cache.publish(f.brick);
    f.brick = -1;
    --m_in_flight;
  }
}

const unsigned char* BrickService::device_part(std::int64_t brick, std::size_t n, const FieldView& part,
                                               std::vector<unsigned char>& spare) {
  const std::pair<std::int64_t, std::size_t> key{brick, n};
  if (const auto it = m_parts.find(key); it != m_parts.end()) return it->second.data();
  const std::size_t bytes = static_cast<std::size_t>(part.vertex_count()) * dtype_size(part.dtype);
  std::vector<unsigned char>* into = &spare;
  if (m_parts_bytes + bytes <= m_parts_cap) {
    into = &m_parts[key];
    m_parts_bytes += bytes;
  }
  into->resize(bytes);
  copy_device_part(into->data(), bytes, m_own[n - m_first_own], part);
  return into->data();
}

void BrickService::copy_device_part(unsigned char* dst, std::size_t bytes, const FieldBlock& block,
                                    const FieldView& part) {
  try {
    cuda_copy_box_to_host(dst, part, block.cuda_stream);
    m_traffic.bytes_from_device += bytes;
  } catch (const std::exception& e) {
    std::memset(dst, 0, bytes);
    const std::string where = block.domain >= 0 ? "domain " + std::to_string(block.domain) : "the field";
    m_cache.fail("copying a brick of this rank's " + where + " from device memory failed: " + e.what());
  }
}

void BrickService::complete_sends() {
  if (m_sends.empty()) return;
  int done = 0;
  check(MPI_Testall(static_cast<int>(m_sends.size()), m_sends.data(), &done, MPI_STATUSES_IGNORE), "MPI_Testall");
  if (done) {
    m_sends.clear();
    m_send_copies.clear();
  }
}

void BrickService::drain() {
  // Finish this rank's own fetches first (a failed cache still gets its bricks: the data
  // are harmless, and the owners expect their replies to be received)
  while (!idle()) {
    if (m_cache.failed()) m_pending.clear();  // nobody waits for them any more
    progress(std::chrono::microseconds(0));
  }
  MPI_Request barrier = MPI_REQUEST_NULL;
  check(MPI_Ibarrier(m_comm, &barrier), "MPI_Ibarrier");
  for (int done = 0; !done;) {
    serve_requests();
    complete_sends();
    check(MPI_Test(&barrier, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (!done) std::this_thread::yield();
  }
  if (!m_sends.empty())
    check(MPI_Waitall(static_cast<int>(m_sends.size()), m_sends.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
  m_sends.clear();
  m_send_copies.clear();
}

}  // namespace tessera::insitu
