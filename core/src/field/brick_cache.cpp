/// BrickCache: the slow paths (miss, publish, flush, failure) under one mutex; the hit path
/// (find) is one atomic load. See brick_cache.h for the protocol.
#include <tessera/brick_cache.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace tessera {
namespace {

/// Per-brick state byte (the directory pointer says "resident" on its own).
enum : std::uint8_t {
  kAbsent = 0,    ///< not resident, nobody asked
  kWanted = 1,    ///< a worker asked; in the FIFO, not yet handed to the service
  kTaken = 2,     ///< handed to the service by take_wanted, no slot yet
  kReserved = 3,  ///< has a slot being filled (not visible to workers)
  kResident = 4,  ///< published: m_dir holds its slot
};

/// Wanted bricks never outnumber the workers blocked at once; the FIFO is reserved for this
/// many so that acquire does not allocate in practice.
constexpr std::size_t kFifoReserve = 1024;

}  // namespace

struct BrickCache::State {
  std::mutex mu;
  std::condition_variable workers;  ///< acquire and enter_tile wait here
  std::condition_variable service;  ///< take_wanted waits here
  /// capacity slots; default-initialised (new[] without ()), so the pages are reserved and
  /// only touched, i.e. made resident, as bricks arrive
  std::unique_ptr<unsigned char[]> pool;
  std::vector<unsigned char> zero;      ///< one slot of zeros, what acquire returns after fail()
  std::vector<std::uint8_t> state;      ///< per brick
  std::vector<std::uint32_t> waiters;   ///< per brick: workers blocked in acquire on it
  std::vector<std::int64_t> owner;      ///< per slot: its brick, -1 when free
  std::vector<std::uint64_t> slot_seq;  ///< per slot: when its brick was published (eviction order)
  std::uint64_t next_seq = 0;
  std::vector<std::size_t> free_slots;
  std::unordered_map<std::int64_t, std::size_t> reserved;  ///< brick -> slot, not yet published
  std::vector<std::int64_t> fifo;                          ///< wanted bricks, oldest first, from `fifo_head`
  std::size_t fifo_head = 0;
  long active = 0;  ///< workers inside a tile and not blocked in acquire
  bool flush_pending = false;
  std::string why;
  BrickCacheStats stats;
  std::uint64_t resident = 0;

  bool flush_possible() const { return active <= 0 && reserved.empty(); }
};

BrickGrid BrickGrid::make(const std::int64_t dims[3], DType dtype, int shift) {
  if (shift < 1 || shift > 10)
    throw std::invalid_argument("brick shift " + std::to_string(shift) + " is outside [1, 10]");
  BrickGrid g;
  g.dtype = dtype;
  g.shift = shift;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] < 1)
      throw std::invalid_argument("brick grid: dims[" + std::to_string(a) + "] = " + std::to_string(dims[a]) +
                                  " must be >= 1");
    g.dims[a] = dims[a];
    g.bricks[a] = (dims[a] + g.edge() - 1) >> shift;
  }
  return g;
}

void BrickGrid::box(std::int64_t b, std::int64_t lo[3], std::int64_t hi[3]) const {
  const std::int64_t c[3] = {b % bricks[0], (b / bricks[0]) % bricks[1], b / (bricks[0] * bricks[1])};
  for (int a = 0; a < 3; ++a) {
    lo[a] = c[a] << shift;
    hi[a] = std::min(dims[a], lo[a] + edge());
  }
}

std::uint64_t BrickCache::bytes_for(const BrickGrid& grid, std::size_t capacity) {
  const std::uint64_t n = static_cast<std::uint64_t>(grid.brick_count());
  // directory pointer, state byte, waiter count; the in-place table
  const std::uint64_t per_brick = sizeof(std::atomic<const unsigned char*>) + 1 + sizeof(std::uint32_t);
  return n * per_brick + in_place_entries(grid) * sizeof(std::int32_t) +
         (static_cast<std::uint64_t>(capacity) + 1) * grid.slot_bytes() +
         static_cast<std::uint64_t>(capacity) * (sizeof(std::int64_t) + sizeof(std::size_t));
}

BrickCache::BrickCache(const BrickGrid& grid, std::size_t capacity)
    : m_grid(grid), m_capacity(capacity), m_state(std::make_unique<State>()) {
  if (capacity < 1) throw std::invalid_argument("brick cache capacity must be >= 1 slot");
  const auto n = static_cast<std::size_t>(grid.brick_count());
  m_dir = std::make_unique<std::atomic<const unsigned char*>[]>(n);
  m_in_place_cells.reset(new std::int32_t[in_place_entries(grid)]);  // filled by set_in_place
  State& s = *m_state;
  s.pool.reset(new unsigned char[capacity * grid.slot_bytes()]);
  s.zero.assign(grid.slot_bytes(), 0);
  s.state.assign(n, kAbsent);
  s.waiters.assign(n, 0);
  s.fifo.reserve(kFifoReserve);
  reset();
}

BrickCache::~BrickCache() = default;

std::uint64_t BrickCache::allocated_bytes() const { return bytes_for(m_grid, m_capacity); }

const unsigned char* BrickCache::acquire(std::int64_t b) noexcept {
  State& s = *m_state;
  std::unique_lock lock(s.mu);
  const unsigned char* slot = find(b);
  if (slot) return slot;  // published between the caller's find and here
  if (m_failed.load(std::memory_order_relaxed)) return s.zero.data();
  auto& st = s.state[static_cast<std::size_t>(b)];
  if (st == kAbsent) {
    st = kWanted;
    s.fifo.push_back(b);
  }
  ++s.stats.misses;
  // Blocked: quiescent until publish(b) counts this worker active again (so that no flush
  // can take b away before this worker has read it)
  ++s.waiters[static_cast<std::size_t>(b)];
  --s.active;
  s.service.notify_one();
  s.workers.wait(lock, [&] { return find(b) != nullptr || m_failed.load(std::memory_order_relaxed); });
  slot = find(b);
  if (slot) return slot;
  // Failed while waiting: undo the wait ourselves
  --s.waiters[static_cast<std::size_t>(b)];
  ++s.active;
  return s.zero.data();
}

void BrickCache::enter_tile() noexcept {
  State& s = *m_state;
  std::unique_lock lock(s.mu);
  s.workers.wait(lock, [&] { return !s.flush_pending || m_failed.load(std::memory_order_relaxed); });
  ++s.active;
}

void BrickCache::leave_tile() noexcept {
  State& s = *m_state;
  std::lock_guard lock(s.mu);
  --s.active;
  if (s.flush_pending && s.flush_possible()) s.service.notify_one();
}

void BrickCache::take_wanted(std::vector<std::int64_t>& out, std::chrono::microseconds wait) {
  State& s = *m_state;
  std::unique_lock lock(s.mu);
  s.service.wait_for(lock, wait, [&] {
    return s.fifo_head < s.fifo.size() || m_failed.load(std::memory_order_relaxed) ||
           (s.flush_pending && s.flush_possible());
  });
  for (; s.fifo_head < s.fifo.size(); ++s.fifo_head) {
    const std::int64_t b = s.fifo[s.fifo_head];
    s.state[static_cast<std::size_t>(b)] = kTaken;
    out.push_back(b);
  }
  s.fifo.clear();
  s.fifo_head = 0;
}

unsigned char* BrickCache::reserve(std::int64_t b) {
  State& s = *m_state;
  std::lock_guard lock(s.mu);
  if (b < 0 || b >= m_grid.brick_count())
    throw std::out_of_range("brick " + std::to_string(b) + " outside the grid of " +
                            std::to_string(m_grid.brick_count()));
  if (s.free_slots.empty()) return nullptr;
  const std::size_t slot = s.free_slots.back();
  s.free_slots.pop_back();
  s.owner[slot] = b;
  s.reserved.emplace(b, slot);
  s.state[static_cast<std::size_t>(b)] = kReserved;
  return s.pool.get() + slot * m_grid.slot_bytes();
}

void BrickCache::publish(std::int64_t b) {
  State& s = *m_state;
  {
    std::lock_guard lock(s.mu);
    const auto it = s.reserved.find(b);
    if (it == s.reserved.end())
      throw std::logic_error("brick " + std::to_string(b) + " published without a reserved slot");
    const unsigned char* slot = s.pool.get() + it->second * m_grid.slot_bytes();
    s.slot_seq[it->second] = ++s.next_seq;
    s.reserved.erase(it);
    m_dir[static_cast<std::size_t>(b)].store(slot, std::memory_order_release);
    s.state[static_cast<std::size_t>(b)] = kResident;
    ++s.stats.fetched;
    s.stats.peak_resident = std::max(s.stats.peak_resident, ++s.resident);
    // Its waiters are active again from now on: they read b before any flush can happen
    auto& w = s.waiters[static_cast<std::size_t>(b)];
    s.active += w;
    w = 0;
  }
  s.workers.notify_all();
}

bool BrickCache::try_flush() {
  State& s = *m_state;
  {
    std::lock_guard lock(s.mu);
    if (!s.flush_possible()) {
      s.flush_pending = true;
      return false;
    }
    // Evict the older half of the resident bricks (by publication order; at least one):
    // the newer half is what the tiles being rendered now are using
    std::vector<std::pair<std::uint64_t, std::size_t>> resident;
    resident.reserve(m_capacity);
    for (std::size_t slot = 0; slot < m_capacity; ++slot)
      if (s.owner[slot] >= 0) resident.emplace_back(s.slot_seq[slot], slot);
    std::sort(resident.begin(), resident.end());
    const std::size_t evict = std::max<std::size_t>(1, (resident.size() + 1) / 2);
    for (std::size_t n = 0; n < evict && n < resident.size(); ++n) {
      const std::size_t slot = resident[n].second;
      const std::int64_t b = s.owner[slot];
      m_dir[static_cast<std::size_t>(b)].store(nullptr, std::memory_order_relaxed);
      s.state[static_cast<std::size_t>(b)] = kAbsent;
      s.owner[slot] = -1;
      s.free_slots.push_back(slot);
      --s.resident;
    }
    ++s.stats.flushes;
    s.flush_pending = false;
  }
  s.workers.notify_all();  // enter_tile may go on
  return true;
}

void BrickCache::fail(const std::string& why) {
  State& s = *m_state;
  {
    std::lock_guard lock(s.mu);
    if (!m_failed.load(std::memory_order_relaxed)) s.why = why;
    m_failed.store(true, std::memory_order_release);
  }
  s.workers.notify_all();
  s.service.notify_all();
}

std::string BrickCache::failure() const {
  std::lock_guard lock(m_state->mu);
  return m_state->why;
}

void BrickCache::reset() {
  State& s = *m_state;
  std::lock_guard lock(s.mu);
  const auto n = static_cast<std::size_t>(m_grid.brick_count());
  for (std::size_t b = 0; b < n; ++b) m_dir[b].store(nullptr, std::memory_order_relaxed);
  std::fill(s.state.begin(), s.state.end(), kAbsent);
  std::fill(s.waiters.begin(), s.waiters.end(), 0u);
  s.owner.assign(m_capacity, -1);
  s.slot_seq.assign(m_capacity, 0);
  s.next_seq = 0;
  s.free_slots.clear();
  for (std::size_t slot = m_capacity; slot-- > 0;) s.free_slots.push_back(slot);
  s.reserved.clear();
  s.fifo.clear();
  s.fifo_head = 0;
  s.active = 0;
  s.flush_pending = false;
  s.why.clear();
  s.stats = BrickCacheStats{};
  s.resident = 0;
  m_failed.store(false, std::memory_order_release);
}

BrickCacheStats BrickCache::stats() const {
  std::lock_guard lock(m_state->mu);
  return m_state->stats;
}

}  // namespace tessera
