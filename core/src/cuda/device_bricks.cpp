/// DeviceBricks (device_bricks.h): the device's pool of a distributed field's bricks.
#include "cuda/device_bricks.h"

#include <tessera/memory_estimate.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace tessera::cuda {

// The host vectors per brick as the adapter's memory estimate counts them
static_assert(sizeof(const unsigned char*) + 2 * sizeof(std::uint64_t) + 1 + 1 <= kGpuHostBytesPerBrick);

namespace {

constexpr std::uint64_t kAlign = 256;

std::uint64_t aligned(std::uint64_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

/// Device bytes of everything but the slots: directory, flags, use marks, two lists of
/// `capacity`, counts, a byte per thread.
std::uint64_t table_bytes(const BrickGrid& g, std::size_t capacity, std::uint64_t threads) {
  const auto n = static_cast<std::uint64_t>(g.brick_count());
  return aligned(n * sizeof(const unsigned char*)) + aligned(n * sizeof(unsigned int)) + aligned(n) +
         2 * aligned(capacity * sizeof(std::int64_t)) + aligned(2 * sizeof(unsigned long long)) + aligned(threads);
}

}  // namespace

BrickGrid DeviceBricks::grid_of(const PagedFieldView& v) { return BrickGrid::make(v.dims, v.dtype, v.shift); }

std::uint64_t DeviceBricks::bytes_for(const PagedFieldView& host, std::size_t capacity, std::uint64_t threads) {
  const BrickGrid g = grid_of(host);
  return table_bytes(g, capacity, threads) + capacity * aligned(g.slot_bytes());
}

std::size_t DeviceBricks::capacity_for(const PagedFieldView& host, std::uint64_t bytes, std::uint64_t threads) {
  const BrickGrid g = grid_of(host);
  const std::uint64_t slot = aligned(g.slot_bytes()) + 2 * sizeof(std::int64_t);  // a slot, its list entries
  const std::uint64_t fixed = table_bytes(g, 0, threads) + 2 * kAlign;            // the lists' alignment
  if (bytes <= fixed) return 0;
  return static_cast<std::size_t>(
      std::min<std::uint64_t>((bytes - fixed) / slot, static_cast<std::uint64_t>(g.brick_count())));
}

DeviceBricks::DeviceBricks(DeviceBackend& backend, const PagedFieldView& host, std::size_t capacity,
                           std::uint64_t threads, unsigned char* base)
    : m_b(backend),
      m_host(host),
      m_grid(grid_of(host)),
      m_capacity(std::max<std::size_t>(capacity, 1)),
      m_threads(threads) {
  const auto n = static_cast<std::uint64_t>(m_grid.brick_count());
  std::uint64_t off = 0;
  m_dir = reinterpret_cast<const unsigned char**>(base + off);
  off += aligned(n * sizeof(const unsigned char*));
  m_wanted = reinterpret_cast<unsigned int*>(base + off);
  off += aligned(n * sizeof(unsigned int));
  m_used = base + off;
  off += aligned(n);
  m_certain = reinterpret_cast<std::int64_t*>(base + off);
  off += aligned(m_capacity * sizeof(std::int64_t));
  m_guess = reinterpret_cast<std::int64_t*>(base + off);
  off += aligned(m_capacity * sizeof(std::int64_t));
  m_count = reinterpret_cast<unsigned long long*>(base + off);
  off += aligned(2 * sizeof(unsigned long long));
  m_path = base + off;
  off += aligned(threads);
  m_pool = base + off;
  m_dir_host.assign(static_cast<std::size_t>(n), nullptr);
  m_serial_of.assign(static_cast<std::size_t>(n), 0);
  m_last.assign(static_cast<std::size_t>(n), 0);
  m_guessed.assign(static_cast<std::size_t>(n), false);
  m_used_host.assign(static_cast<std::size_t>(n), 0);
  m_buffer.assign(m_grid.slot_bytes(), 0);
}

std::uint64_t DeviceBricks::reset() {
  const auto n = static_cast<std::size_t>(m_grid.brick_count());
  std::fill(m_dir_host.begin(), m_dir_host.end(), nullptr);
  m_free.clear();
  const std::uint64_t slot = aligned(m_grid.slot_bytes());
  for (std::size_t i = m_capacity; i-- > 0;) m_free.push_back(m_pool + i * slot);
  m_b.copy_to_device(m_dir, m_dir_host.data(), n * sizeof(const unsigned char*), "brick directory");
  m_b.zero(m_wanted, n * sizeof(unsigned int), "brick flags");
  m_b.zero(m_used, n, "brick use marks");
  m_b.zero(m_count, 2 * sizeof(unsigned long long), "brick counts");
  m_b.zero(m_path, m_threads, "per-thread brick flags");
  const std::uint64_t bytes = n * sizeof(const unsigned char*);
  m_to_device += bytes;
  m_valid = true;
  m_changed = false;
  return bytes;
}

PagedFieldView DeviceBricks::device_view(const void* local) const {
  PagedFieldView v = m_host;
  if (local && m_host.local.data) {
    v.local.data = local;
  } else {
    v.local = FieldView{};
    v.local.dtype = m_host.dtype;
    for (int a = 0; a < 3; ++a) v.lo[a] = v.hi[a] = 0;
  }
  v.in_place = InPlaceTable{};
  v.device.slot = m_dir;
  v.device.wanted = m_wanted;
  v.device.certain = m_certain;
  v.device.guess = m_guess;
  v.device.count = m_count;
  v.device.list_capacity = m_capacity;
  v.device.path_missed = m_path;
  v.device.path_capacity = m_threads;
  v.device.used = m_used;
  return v;
}

bool DeviceBricks::take_noted(std::vector<std::int64_t>& certain, std::vector<std::int64_t>& guesses, bool* more) {
  unsigned long long count[2] = {0, 0};
  m_b.copy_to_host(count, m_count, sizeof count, "brick counts");
  m_to_host += sizeof count;
  certain.clear();
  guesses.clear();
  if (more) *more = count[0] > m_capacity;
  if (count[0] == 0) return false;  // a sample's first miss is certain: nothing missed
  certain.resize(static_cast<std::size_t>(std::min<unsigned long long>(count[0], m_capacity)));
  guesses.resize(static_cast<std::size_t>(std::min<unsigned long long>(count[1], m_capacity)));
  m_b.copy_to_host(certain.data(), m_certain, certain.size() * sizeof(std::int64_t), "bricks noted");
  if (!guesses.empty())
    m_b.copy_to_host(guesses.data(), m_guess, guesses.size() * sizeof(std::int64_t), "bricks noted");
  m_to_host += (certain.size() + guesses.size()) * sizeof(std::int64_t);
  m_b.zero(m_wanted, static_cast<std::size_t>(m_grid.brick_count()) * sizeof(unsigned int), "brick flags");
  m_b.zero(m_count, sizeof count, "brick counts");
  return true;
}

void DeviceBricks::after_launch() {
  const auto n = static_cast<std::size_t>(m_grid.brick_count());
  m_b.copy_to_host(m_used_host.data(), m_used, n, "brick use marks");
  m_to_host += n;
  for (std::size_t b = 0; b < n; ++b)
    if (m_used_host[b]) {
      m_last[b] = m_stamp;
      m_guessed[b] = false;  // read: no longer a mere guess
    }
  m_b.zero(m_used, n, "brick use marks");
  ++m_stamp;
}

void DeviceBricks::fill(std::int64_t b, unsigned char* out) const {
  const std::int64_t e = m_grid.edge();
  std::int64_t lo[3], hi[3];
  m_grid.box(b, lo, hi);
  const std::size_t es = dtype_size(m_grid.dtype);
  BrickCache* cache = m_host.cache;
  // Inside a tile of the host cache: no flush can reuse a slot while its vertices are read
  cache->enter_tile();
  for (std::int64_t k = lo[2]; k < hi[2]; ++k)
    for (std::int64_t j = lo[1]; j < hi[1]; ++j)
      for (std::int64_t i = lo[0]; i < hi[0]; ++i) {
        const std::int64_t at = (((k - lo[2]) * e + (j - lo[1])) * e) + (i - lo[0]);
        detail::store_from_double(m_grid.dtype, out + static_cast<std::size_t>(at) * es, m_host.load(i, j, k));
      }
  cache->leave_tile();
  if (cache->failed()) throw std::runtime_error("distributed field: " + cache->failure());
}

bool DeviceBricks::bring(std::int64_t b, bool guess, std::uint64_t since, BrickRound& r) {
  const auto ub = static_cast<std::size_t>(b);
  if (b < 0 || b >= m_grid.brick_count())
    throw std::logic_error("distributed field: the device noted brick " + std::to_string(b) + " of " +
                           std::to_string(m_grid.brick_count()));
  if (m_dir_host[ub]) {
    if (!guess) m_guessed[ub] = false;
    return true;
  }
  if (m_free.empty()) {
    // A victim (no kernel runs now: nothing reads it): first the bricks the current launch has
    // not read nor asked for, read longest ago first; then its guesses (only for a certain
    // brick); the bricks it read or was sure of last, which means it does not fit
    if (m_victims.empty() && m_next_victim == 0) {
      for (std::size_t i = 0; i < m_dir_host.size(); ++i)
        if (m_dir_host[i]) m_victims.push_back(static_cast<std::int64_t>(i));
      const auto rank = [&](std::int64_t x) {
        const auto ux = static_cast<std::size_t>(x);
        const int kind = m_last[ux] < since ? 0 : m_guessed[ux] ? 1 : 2;
        return std::tuple(kind, m_last[ux], m_serial_of[ux]);
      };
      std::sort(m_victims.begin(), m_victims.end(), [&](std::int64_t x, std::int64_t y) { return rank(x) < rank(y); });
    }
    if (m_next_victim >= m_victims.size()) {
      // Every resident brick came in this round
      if (guess) return false;
      r.overflow = true;
      return true;  // not made resident: the launch is split (or given up)
    }
    const auto old = static_cast<std::size_t>(m_victims[m_next_victim]);
    if (m_last[old] >= since) {  // the current launch's
      if (guess) return false;   // a guess never displaces it
      if (!m_guessed[old]) r.overflow = true;
    }
    ++m_next_victim;
    m_free.push_back(const_cast<unsigned char*>(m_dir_host[old]));
    m_dir_host[old] = nullptr;
    m_changed = true;
  }
  unsigned char* slot = m_free.back();
  m_free.pop_back();
  fill(b, m_buffer.data());
  m_b.copy_to_device(slot, m_buffer.data(), m_grid.slot_bytes(), "brick");
  m_to_device += m_grid.slot_bytes();
  m_dir_host[ub] = slot;
  m_serial_of[ub] = m_serial++;
  m_last[ub] = m_stamp;
  m_guessed[ub] = guess;
  ++r.fetched;
  ++m_fetched;
  m_changed = true;
  return true;
}

BrickRound DeviceBricks::fetch(std::span<const std::int64_t> certain, std::span<const std::int64_t> guesses,
                               std::uint64_t since) {
  BrickRound r;
  m_valid = false;  // until the directory is back on the device
  m_victims.clear();
  m_next_victim = 0;
  for (const std::int64_t b : certain) bring(b, false, since, r);
  for (const std::int64_t b : guesses)
    if (!bring(b, true, since, r)) break;
  if (m_changed) {
    const std::size_t bytes = m_dir_host.size() * sizeof(const unsigned char*);
    m_b.copy_to_device(m_dir, m_dir_host.data(), bytes, "brick directory");
    m_to_device += bytes;
    m_changed = false;
  }
  m_valid = true;
  return r;
}

}  // namespace tessera::cuda
