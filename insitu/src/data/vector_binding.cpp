// A vector's magnitude as the render's field (vector_binding.h).
#include "data/vector_binding.h"

#include <tessera/brick_cache.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace tessera::insitu {
namespace {

std::string box(const FieldBlock& b) {
  return std::to_string(b.view.dims[0]) + "x" + std::to_string(b.view.dims[1]) + "x" + std::to_string(b.view.dims[2]) +
         " at (" + std::to_string(b.offset[0]) + ", " + std::to_string(b.offset[1]) + ", " +
         std::to_string(b.offset[2]) + ")";
}

/// Component c's binding against component 0's: the same association and blocks.
void check_alike(const FieldBinding& first, const FieldBinding& other, const std::string& a, const std::string& b) {
  const std::string pair = "the components of a magnitude, fields '" + a + "' and '" + b + "', ";
  if (first.geometry.association != other.geometry.association)
    throw std::invalid_argument(pair + "have different associations (" +
                                (first.geometry.association == Association::Cell ? "cell" : "vertex") + " and " +
                                (other.geometry.association == Association::Cell ? "cell" : "vertex") +
                                " data): give all three the same");
  if (first.blocks.size() != other.blocks.size())
    throw std::invalid_argument(pair + "are published in " + std::to_string(first.blocks.size()) + " and " +
                                std::to_string(other.blocks.size()) + " blocks on this rank");
  for (std::size_t n = 0; n < first.blocks.size(); ++n) {
    const FieldBlock &p = first.blocks[n], &q = other.blocks[n];  // in_order: the same domain
    bool same = p.domain == q.domain && p.level == q.level;
    for (int d = 0; d < 3; ++d) same = same && p.offset[d] == q.offset[d] && p.view.dims[d] == q.view.dims[d];
    if (!same)
      throw std::invalid_argument(pair + "differ in " +
                                  (p.domain >= 0 ? "domain " + std::to_string(p.domain) : "the grid") + ": " + box(p) +
                                  " and " + box(q) + " elements");
  }
}

/// `b`'s blocks in the order of `first`'s domains (each component's blocks are listed largest
/// first, so a component of other dims may list them in another order); as it is when a domain
/// of one is missing from the other (check_alike then names the difference).
void in_order(const FieldBinding& first, FieldBinding& b) {
  if (first.blocks.size() != b.blocks.size()) return;
  std::vector<FieldBlock> sorted = b.blocks;
  const auto key = [](const FieldBlock& x) { return std::pair{x.domain, x.level}; };
  std::sort(sorted.begin(), sorted.end(), [&](const FieldBlock& x, const FieldBlock& y) { return key(x) < key(y); });
  for (std::size_t n = 0; n < first.blocks.size(); ++n) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), key(first.blocks[n]),
                                     [&](const FieldBlock& x, const std::pair<int, int>& k) { return key(x) < k; });
    if (it == sorted.end() || key(*it) != key(first.blocks[n])) return;
    b.blocks[n] = *it;
  }
}

/// Block n's magnitudes, dense (i fastest).
std::vector<double> stage(const FieldBlock (&parts)[3]) {
  const std::int64_t* d = parts[0].view.dims;
  std::vector<double> out(static_cast<std::size_t>(d[0] * d[1] * d[2]));
  std::size_t e = 0;
  const auto at = [](const FieldView& v, std::int64_t i, std::int64_t j, std::int64_t k) {
    const auto* p = static_cast<const unsigned char*>(v.data) + i * v.byte_strides[0] + j * v.byte_strides[1] +
                    k * v.byte_strides[2];
    return detail::load_as_double(v.dtype, p);
  };
  for (std::int64_t k = 0; k < d[2]; ++k)
    for (std::int64_t j = 0; j < d[1]; ++j)
      for (std::int64_t i = 0; i < d[0]; ++i)
        out[e++] = magnitude(at(parts[0].view, i, j, k), at(parts[1].view, i, j, k), at(parts[2].view, i, j, k));
  return out;
}

}  // namespace

VectorField combine_components(const FieldBinding (&components)[3], const std::string (&names)[3], bool one_rank,
                               std::uint64_t limit_bytes, const std::string& limit_text) {
  FieldBinding c[3] = {components[0], components[1], components[2]};
  for (int n = 1; n < 3; ++n) {
    in_order(c[0], c[n]);
    check_alike(c[0], c[n], names[0], names[n]);
  }
  VectorField v;
  v.binding = c[0];
  if (one_rank && c[0].whole()) {
    MagnitudeField m;
    for (int n = 0; n < 3; ++n) m.components[n] = c[n].blocks[0].view;
    v.in_place = m;
    return v;
  }
  std::uint64_t elements = 0;
  for (const FieldBlock& b : c[0].blocks) elements += static_cast<std::uint64_t>(b.view.vertex_count());
  v.staged_bytes = elements * sizeof(double);
  if (v.staged_bytes > limit_bytes)
    throw std::runtime_error("the magnitude of fields '" + names[0] + "', '" + names[1] + "', '" + names[2] +
                             "' needs " + std::to_string(v.staged_bytes) + " bytes staged on this rank (" +
                             std::to_string(elements) + " elements of float64), over " + limit_text + " (" +
                             std::to_string(limit_bytes) + " bytes)");
  v.staged.reserve(c[0].blocks.size());
  for (std::size_t n = 0; n < c[0].blocks.size(); ++n) {
    const FieldBlock parts[3] = {c[0].blocks[n], c[1].blocks[n], c[2].blocks[n]};
    v.staged.push_back(stage(parts));
    FieldBlock& b = v.binding.blocks[n];
    const std::int64_t* d = b.view.dims;
    b.view = FieldView::contiguous(v.staged.back().data(), DType::Float64, d[0], d[1], d[2]);
  }
  // The largest block (blocks are listed largest first) is the one distributed mode reads
  if (v.binding.local.data) v.binding.local = v.binding.blocks.empty() ? FieldView{} : v.binding.blocks[0].view;
  v.binding.local.dtype = DType::Float64;
  return v;
}

}  // namespace tessera::insitu
