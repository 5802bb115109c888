#include "data/summary_cache.h"

#include "data/hash64.h"

#include <string_view>

#include <utility>

namespace tessera::insitu {

SummaryKey SummaryKey::of(const FieldBinding& binding) {
  SummaryKey k;
  k.local = FieldLayout::of(binding.local);
  for (int a = 0; a < 3; ++a) {
    k.offset[a] = binding.placement.offset[a];
    k.global_dims[a] = binding.placement.global_dims[a];
  }
  k.blocks = binding.blocks.size();
  std::uint64_t h = fnv1a64({});
  for (const FieldBlock& b : binding.blocks) {
    const FieldLayout l = FieldLayout::of(b.view);
    const std::uint64_t words[12] = {reinterpret_cast<std::uintptr_t>(l.data),
                                     static_cast<std::uint64_t>(l.dtype),
                                     static_cast<std::uint64_t>(l.dims[0]),
                                     static_cast<std::uint64_t>(l.dims[1]),
                                     static_cast<std::uint64_t>(l.dims[2]),
                                     static_cast<std::uint64_t>(l.byte_strides[0]),
                                     static_cast<std::uint64_t>(l.byte_strides[1]),
                                     static_cast<std::uint64_t>(l.byte_strides[2]),
                                     static_cast<std::uint64_t>(b.offset[0]),
                                     static_cast<std::uint64_t>(b.offset[1]),
                                     static_cast<std::uint64_t>(b.offset[2]),
                                     static_cast<std::uint32_t>(b.domain) | static_cast<std::uint64_t>(b.level) << 32};
    h = fnv1a64(std::string_view(reinterpret_cast<const char*>(words), sizeof words), h);
  }
  // Refinement levels: the ratios too (a single level hashes as before)
  if (binding.nlevels > 1) {
    const int levels[kMaxAmrLevels] = {binding.nlevels,       binding.refinement[0], binding.refinement[1],
                                       binding.refinement[2], binding.refinement[3], binding.refinement[4],
                                       binding.refinement[5], binding.refinement[6]};
    h = fnv1a64(std::string_view(reinterpret_cast<const char*>(levels), sizeof levels), h);
  }
  k.blocks_hash = h;
  return k;
}

bool SummaryKey::operator==(const SummaryKey& o) const {
  if (!(local == o.local) || blocks != o.blocks || blocks_hash != o.blocks_hash) return false;
  for (int a = 0; a < 3; ++a)
    if (offset[a] != o.offset[a] || global_dims[a] != o.global_dims[a]) return false;
  return true;
}

std::shared_ptr<const FieldSummary> SummaryCache::Entry::find(int edge) const {
  for (const auto& s : summaries)
    if (edge == 0 || s->edge() == edge) return s;
  return nullptr;
}

void SummaryCache::Entry::keep(std::shared_ptr<const FieldSummary> s) {
  for (auto& old : summaries)
    if (old->edge() == s->edge()) {
      old = std::move(s);
      return;
    }
  summaries.push_back(std::move(s));
}

void SummaryCache::mark_unchanged(const std::string& name) { entry(name).marked = true; }

void SummaryCache::begin_call() {
  for (Entry& e : m_entries) {
    e.carried = e.marked;
    e.marked = false;
    e.decided = false;
    e.kept = false;
    if (!e.carried) e.summaries.clear();
  }
}

SummaryCache::Entry& SummaryCache::entry(const std::string& name) {
  for (Entry& e : m_entries)
    if (e.name == name) return e;
  m_entries.emplace_back();
  m_entries.back().name = name;
  return m_entries.back();
}

}  // namespace tessera::insitu
