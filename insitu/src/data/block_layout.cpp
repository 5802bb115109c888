// Whether blocks tile the global grid, in O(N log N) (block_layout.h says how).
#include "data/block_layout.h"

#include <algorithm>
#include <climits>
#include <string>
#include <tuple>
#include <vector>

namespace tessera::insitu {
namespace {

std::string box_text(const std::int64_t offset[3], const std::int64_t dims[3]) {
  std::string s = "[";
  for (int a = 0; a < 3; ++a)
    s += (a ? ", " : "") + std::to_string(offset[a]) + ".." + std::to_string(offset[a] + dims[a]);
  return s + ")";
}

std::string dims_text(const std::int64_t dims[3]) {
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
}

/// The first 8 blocks by name: "rank 0 [0..4, 0..8, 0..8), rank 1 ...".
std::string blocks_text(std::span<const BlockRecord> blocks) {
  constexpr std::size_t kShown = 8;
  std::string s;
  for (std::size_t r = 0; r < blocks.size() && r < kShown; ++r)
    s += (r ? ", " : "") + block_name(blocks[r]) + " " + box_text(blocks[r].offset, blocks[r].dims);
  if (blocks.size() > kShown) s += " and " + std::to_string(blocks.size() - kShown) + " more blocks";
  return s;
}

bool overlap(const BlockRecord& a, const BlockRecord& b) {
  for (int x = 0; x < 3; ++x)
    if (!(a.offset[x] < b.offset[x] + b.dims[x] && b.offset[x] < a.offset[x] + a.dims[x])) return false;
  return true;
}

/// A pair of overlapping blocks (indices, first < second in input order), found by a sweep
/// along i within kMaxPairTests comparisons; {-1, -1} if none was found.
std::pair<std::int64_t, std::int64_t> overlapping_pair(std::span<const BlockRecord> blocks) {
  std::vector<std::int64_t> order(blocks.size());
  for (std::size_t n = 0; n < order.size(); ++n) order[n] = static_cast<std::int64_t>(n);
  // Blocks that start at the same element overlap: found in O(N log N) whatever the budget
  std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
    const BlockRecord &x = blocks[a], &y = blocks[b];
    return std::tie(x.offset[0], x.offset[1], x.offset[2], a) < std::tie(y.offset[0], y.offset[1], y.offset[2], b);
  });
  for (std::size_t n = 1; n < order.size(); ++n) {
    const BlockRecord &x = blocks[order[n - 1]], &y = blocks[order[n]];
    if (x.offset[0] == y.offset[0] && x.offset[1] == y.offset[1] && x.offset[2] == y.offset[2])
      return {std::min(order[n - 1], order[n]), std::max(order[n - 1], order[n])};
  }
  // A sweep along i (order is sorted by i first)
  std::vector<std::int64_t> active;  // blocks whose i range may still meet later ones
  std::int64_t tests = 0;
  std::pair<std::int64_t, std::int64_t> best{-1, -1};
  for (std::int64_t n : order) {
    const BlockRecord& b = blocks[n];
    tests += static_cast<std::int64_t>(active.size());
    if (tests > kMaxPairTests) return best;
    std::erase_if(active, [&](std::int64_t q) { return blocks[q].offset[0] + blocks[q].dims[0] <= b.offset[0]; });
    for (std::int64_t q : active) {
      if (++tests > kMaxPairTests) return best;
      if (overlap(blocks[q], b)) {
        const std::pair<std::int64_t, std::int64_t> p{std::min(q, n), std::max(q, n)};
        if (best.first < 0 || p < best) best = p;
      }
    }
    if (best.first >= 0) return best;
    active.push_back(n);
  }
  return best;
}

/// A corner point, packed: 31 bits per axis (global dims <= INT_MAX).
using Key = unsigned __int128;
Key key(std::int64_t i, std::int64_t j, std::int64_t k) {
  return (static_cast<Key>(static_cast<std::uint64_t>(k)) << 64) |
         (static_cast<Key>(static_cast<std::uint64_t>(j)) << 32) | static_cast<Key>(static_cast<std::uint64_t>(i));
}

void add_corners(std::vector<Key>& keys, const std::int64_t lo[3], const std::int64_t hi[3]) {
  for (int c = 0; c < 8; ++c) keys.push_back(key(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]));
}

}  // namespace

std::string block_name(const BlockRecord& b) {
  return "rank " + std::to_string(b.rank) + (b.domain >= 0 ? " domain " + std::to_string(b.domain) : std::string());
}

void check_tiling(std::span<const BlockRecord> blocks, const std::int64_t global[3], const char* elements) {
  const std::string elems = elements;
  for (int a = 0; a < 3; ++a)
    if (global[a] < 1 || global[a] > INT_MAX)
      throw LayoutError("global_dims must be in [1, " + std::to_string(INT_MAX) + "]");
  // Each block inside the grid; the element counts
  __int128 covered = 0;
  for (const BlockRecord& b : blocks) {
    for (int a = 0; a < 3; ++a)
      if (b.offset[a] < 0 || b.dims[a] < 1 || b.offset[a] + b.dims[a] > global[a])
        throw LayoutError(block_name(b) + "'s real " + elems + " " + box_text(b.offset, b.dims) +
                          " leave the global grid " + dims_text(global));
    covered += static_cast<__int128>(b.dims[0]) * b.dims[1] * b.dims[2];
  }
  const __int128 total = static_cast<__int128>(global[0]) * global[1] * global[2];

  // Corner parity (see the header): the corners that occur an odd number of times must be
  // exactly the grid's 8
  bool parity_ok = false;
  if (covered == total) {
    std::vector<Key> keys;
    keys.reserve(8 * blocks.size());
    for (const BlockRecord& b : blocks) {
      const std::int64_t hi[3] = {b.offset[0] + b.dims[0], b.offset[1] + b.dims[1], b.offset[2] + b.dims[2]};
      add_corners(keys, b.offset, hi);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<Key> odd;
    for (std::size_t n = 0; n < keys.size();) {
      std::size_t m = n;
      while (m < keys.size() && keys[m] == keys[n]) ++m;
      if ((m - n) % 2 == 1) {
        odd.push_back(keys[n]);
        if (odd.size() > 8) break;
      }
      n = m;
    }
    std::vector<Key> grid;
    const std::int64_t zero[3] = {0, 0, 0};
    add_corners(grid, zero, global);
    std::sort(grid.begin(), grid.end());
    grid.erase(std::unique(grid.begin(), grid.end()), grid.end());  // (never: dims >= 1)
    parity_ok = odd == grid;
  }
  if (parity_ok) return;

  // Not a tiling: name an overlapping pair when there is one, else the coverage
  const auto [p, q] = overlapping_pair(blocks);
  if (p >= 0) {
    const BlockRecord& a = blocks[static_cast<std::size_t>(p)];
    const BlockRecord& b = blocks[static_cast<std::size_t>(q)];
    throw LayoutError(block_name(a) + "'s real " + elems + " " + box_text(a.offset, a.dims) + " overlap " +
                      block_name(b) + "'s " + box_text(b.offset, b.dims) + " (declare shared " + elems +
                      " as ghosts on all but one " + (a.domain >= 0 || b.domain >= 0 ? "domain" : "rank") + ")");
  }
  const auto count = [](__int128 v) { return std::to_string(static_cast<long long>(v)); };
  const bool domains = !blocks.empty() && blocks[0].domain >= 0;
  throw LayoutError(std::string(domains ? "the domains' real " : "the ranks' real ") + elems + " cover " +
                    count(covered) + " of the " + count(total) + " global " + elems + " " + dims_text(global) +
                    (covered == total ? " but overlap and leave a gap (no overlapping pair found within " +
                                            std::to_string(kMaxPairTests) + " comparisons)"
                                      : "") +
                    " (real " + elems + ": " + blocks_text(blocks) + ")");
}

}  // namespace tessera::insitu
