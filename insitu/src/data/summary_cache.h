#pragma once
/// SummaryCache: per field (by the simulation's name) the FieldSummaries of the global field
/// the adapter renders, so that a field is read once per execute call however many renders
/// and Cinema cameras use it, and not at all in a call where the simulation said that its
/// values did not change (tessera_field_unchanged / Adapter::field_unchanged).
///
/// Lifetime of a summary: made during a call, it serves every later use of the field in that
/// call. It survives into the next call only if the field was marked unchanged before it, the
/// field's local layout (data pointer after ghosts, dtype, dims, strides, global placement) is
/// the same as when the summary was made, and, with MPI, all ranks agree on both (decided once
/// per field and call, see Pass in render_pass.cpp). A call without the mark drops them, so a
/// summary never outlives a change of values the simulation did not rule out.
///
/// Not thread-safe (the adapter is used by one thread); not collective: the one agreement is
/// made by the caller.
#include "data/field_binding.h"

#include <tessera/field_summary.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace tessera::insitu {

/// Where a field's summaries came from: compared, never dereferenced.
struct SummaryKey {
  FieldLayout local;  ///< this rank's real vertices
  std::int64_t offset[3] = {0, 0, 0};
  std::int64_t global_dims[3] = {0, 0, 0};
  /// Every block of this rank (tessera_execute_domains): their count and a hash of their
  /// layouts and offsets.
  std::uint64_t blocks = 0, blocks_hash = 0;

  static SummaryKey of(const FieldBinding& binding);
  bool operator==(const SummaryKey& o) const;
};

class SummaryCache {
 public:
  struct Entry {
    std::string name;
    bool marked = false;   ///< unchanged at the next call (set by mark_unchanged)
    bool carried = false;  ///< this call: was marked when the call began
    bool decided = false;  ///< this call: the ranks have decided on keeping `summaries`
    bool kept = false;     ///< this call: they did keep them (the same on every rank)
    SummaryKey key;
    std::vector<std::shared_ptr<const FieldSummary>> summaries;  ///< one per macrocell edge

    /// The summary for `edge`, or any one when edge is 0; null when there is none.
    std::shared_ptr<const FieldSummary> find(int edge) const;
    /// Adds s, replacing one of the same edge.
    void keep(std::shared_ptr<const FieldSummary> s);
  };

  /// The simulation's promise that the values of `name` at the next execute equal those at
  /// the last one.
  void mark_unchanged(const std::string& name);
  /// At the start of every execute call: consumes the marks and drops the summaries of every
  /// field that was not marked.
  void begin_call();
  /// The field's entry (created empty on first use).
  Entry& entry(const std::string& name);
  void clear() { m_entries.clear(); }

 private:
  std::deque<Entry> m_entries;  // stable references
};

}  // namespace tessera::insitu
