#include "agreement/rank_agreement.h"

#include "agreement/publication_agreement.h"
#include "data/domain_binding.h"

#include "data/hash64.h"
#include "outputs/error_policy.h"

#include <tessera/message_text.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <vector>

namespace tessera::insitu {
namespace {

// ---------------------------------------------------------------------------------------
// Formatting

/// A value quoted for a message, cut to `max` characters.
/// Escaped as message_text.h says: `'abc'`, `'abc...' (5000 characters)`.
std::string quoted(std::string_view s, std::size_t max = 60) {
  std::string q(1, '\'');
  if (s.size() <= max) return q.append(printable_text(s)).append(1, '\'');
  const std::string cut = shown_value(s, max);
  const std::size_t dots = cut.rfind("... (");
  return q.append(cut, 0, dots).append("...'").append(cut, dots + 3);
}

std::string rank_name(int r) { return "rank " + std::to_string(r); }

// ---------------------------------------------------------------------------------------
// tessera_open: config and environment

constexpr std::size_t kKnobs = kEnvironmentKnobs.size();
constexpr std::size_t kKnobText = 48;  ///< raw value bytes carried for the message

/// What each rank tells the others at open (raw bytes through one allgather).
struct OpenRecord {
  std::uint64_t config_hash[2];
  std::uint64_t config_bytes;
  std::uint64_t knob_set[kKnobs];      ///< 1 if the variable is set (even to "")
  std::uint64_t knob_hash[kKnobs][2];  ///< of the whole raw value
  std::uint64_t knob_bytes[kKnobs];
  char knob_text[kKnobs][kKnobText];  ///< its first bytes, NUL-padded
};
static_assert(std::is_trivially_copyable_v<OpenRecord>);

OpenRecord open_record(const std::string& config) {
  OpenRecord rec{};
  rec.config_hash[0] = fnv1a64(config);
  rec.config_hash[1] = murmur64a(config);
  rec.config_bytes = config.size();
  for (std::size_t k = 0; k < kKnobs; ++k) {
    const char* v = std::getenv(kEnvironmentKnobs[k]);
    if (!v) continue;
    const std::string_view s(v);
    rec.knob_set[k] = 1;
    rec.knob_hash[k][0] = fnv1a64(s);
    rec.knob_hash[k][1] = murmur64a(s);
    rec.knob_bytes[k] = s.size();
    std::memcpy(rec.knob_text[k], s.data(), std::min(s.size(), kKnobText));
  }
  return rec;
}

bool same_config(const OpenRecord& a, const OpenRecord& b) {
  return a.config_bytes == b.config_bytes && a.config_hash[0] == b.config_hash[0] &&
         a.config_hash[1] == b.config_hash[1];
}

bool same_knob(const OpenRecord& a, const OpenRecord& b, std::size_t k) {
  return a.knob_set[k] == b.knob_set[k] && a.knob_bytes[k] == b.knob_bytes[k] &&
         a.knob_hash[k][0] == b.knob_hash[k][0] && a.knob_hash[k][1] == b.knob_hash[k][1];
}

std::string knob_value(const OpenRecord& rec, std::size_t k) {
  if (!rec.knob_set[k]) return "unset";
  if (rec.knob_bytes[k] == 0) return "'' (set but empty)";
  const std::string_view text(rec.knob_text[k], std::min<std::size_t>(rec.knob_bytes[k], kKnobText));
  if (rec.knob_bytes[k] <= kKnobText) return quoted(text, kKnobText);
  std::string q(1, '\'');
  return q.append(printable_text(text)).append("...' (" + std::to_string(rec.knob_bytes[k]) + " characters)");
}

/// The lines of `text`, without their newlines (a final newline ends the last line).
std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) {
      if (start < text.size()) lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

std::string_view trimmed(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t");
  return first == std::string_view::npos ? std::string_view() : s.substr(first);
}

// ---------------------------------------------------------------------------------------
// execute: step, renders, grid

constexpr std::size_t kFiredWords = 4;  ///< renders named individually: the first 256

struct CallRecord {
  std::uint64_t kind;  ///< CallKind
  std::int64_t step;
  std::uint64_t fired_bits[kFiredWords];        ///< fires or may fire
  std::uint64_t conditional_bits[kFiredWords];  ///< fires if its `when` trigger does
  std::uint64_t fired_hash;                     ///< over every render's flag (configs of any size)
  std::uint64_t plan_bits;  ///< the render-budget plan (a double): rank 0's is adopted, not compared
  PublicationRecord pub;    ///< grid or mesh, and field list (publication_agreement.h)
};
static_assert(std::is_trivially_copyable_v<CallRecord>);

CallRecord call_record(const CallView& call) {
  CallRecord rec{};
  rec.kind = static_cast<std::uint64_t>(call.kind);
  rec.step = call.step;
  std::uint64_t h = fnv1a64({});
  for (std::size_t i = 0; i < call.fired.size(); ++i) {
    const unsigned char f = std::min<unsigned char>(call.fired[i], 2);
    const std::uint64_t bit = std::uint64_t{1} << (i % 64);
    if (f != 0 && i < 64 * kFiredWords) rec.fired_bits[i / 64] |= bit;
    if (f == 2 && i < 64 * kFiredWords) rec.conditional_bits[i / 64] |= bit;
    const char byte = static_cast<char>(0x35u + f);
    h = fnv1a64(std::string_view(&byte, 1), h);
  }
  rec.fired_hash = h;
  rec.plan_bits = std::bit_cast<std::uint64_t>(call.plan);
  if (call.kind != CallKind::Close)
    rec.pub = call.mesh_call ? mesh_call_record()
                             : publication_record(call.domains_call, call.grid, call.mesh, call.domains, call.ndomains);
  return rec;
}

bool same_fired(const CallRecord& a, const CallRecord& b) {
  return a.fired_hash == b.fired_hash && std::equal(a.fired_bits, a.fired_bits + kFiredWords, b.fired_bits) &&
         std::equal(a.conditional_bits, a.conditional_bits + kFiredWords, b.conditional_bits);
}

/// The renders that fire on one rank and not on the other, named (first few).
std::string fired_difference(const CallRecord& mine, const CallRecord& ref, int r, const CallView& call) {
  std::string on_mine, on_ref, forced_mine, forced_ref;
  int listed = 0;
  const std::size_t n = std::min(call.renders.size(), 64 * kFiredWords);
  const auto bit = [](const std::uint64_t* bits, std::size_t i) { return ((bits[i / 64] >> (i % 64)) & 1) != 0; };
  for (std::size_t i = 0; i < n && listed < 4; ++i) {
    const bool a = bit(mine.fired_bits, i), b = bit(ref.fired_bits, i);
    const bool ca = bit(mine.conditional_bits, i), cb = bit(ref.conditional_bits, i);
    if (a == b && ca == cb) continue;
    std::string& list = a != b ? (a ? on_mine : on_ref) : (ca ? forced_ref : forced_mine);
    if (!list.empty()) list += ", ";
    list += quoted(call.renders[i].name, 40);
    ++listed;
  }
  const std::string who = rank_name(r);
  std::string s;
  const auto add = [&s](const std::string& names, const std::string& what) {
    if (names.empty()) return;
    if (!s.empty()) s += "; ";
    s += "render " + names + what;
  };
  add(on_mine, " fires on " + who + " but not on rank 0");
  add(on_ref, " fires on rank 0 but not on " + who);
  add(forced_mine, " is forced (final step) on " + who + " but waits for its `when` trigger on rank 0");
  add(forced_ref, " is forced (final step) on rank 0 but waits for its `when` trigger on " + who);
  if (s.empty()) s = "the sets of renders differ between " + who + " and rank 0";
  return s + " (a final_step flag that differs between ranks does this)";
}

/// "closed the adapter", "called execute_final at step 7", ...
std::string call_name(const CallRecord& rec) {
  switch (static_cast<CallKind>(rec.kind)) {
    case CallKind::Close: return "closed the adapter";
    case CallKind::Final: return "called execute_final at step " + std::to_string(rec.step);
    case CallKind::Execute: return "called execute at step " + std::to_string(rec.step);
  }
  return "made call kind " + std::to_string(rec.kind);
}

}  // namespace

std::string first_difference(const std::string& a, const std::string& b) {
  const std::vector<std::string_view> la = lines_of(a), lb = lines_of(b);
  const std::size_t n = std::max(la.size(), lb.size());
  for (std::size_t i = 0; i < n; ++i) {
    const bool ha = i < la.size(), hb = i < lb.size();
    if (ha && hb && la[i] == lb[i]) continue;
    const std::string sa = ha ? quoted(trimmed(la[i])) : std::string("end of text");
    const std::string sb = hb ? quoted(trimmed(lb[i])) : std::string("end of text");
    return "line " + std::to_string(i + 1) + ": " + sa + " vs " + sb;
  }
  return {};
}

std::optional<Disagreement> agree_on_open(ParallelContext& ctx, const std::string& effective_config) {
  const int n = ctx.size();
  const OpenRecord mine = open_record(effective_config);
  std::vector<OpenRecord> all(static_cast<std::size_t>(n));
  ctx.allgather(&mine, sizeof mine, all.data());

  // The first rank whose config, and the first whose environment, differs from rank 0's
  int config_rank = -1, knob_rank = -1;
  std::size_t knob = 0;
  for (int r = 1; r < n; ++r) {
    if (config_rank < 0 && !same_config(all[r], all[0])) config_rank = r;
    for (std::size_t k = 0; k < kKnobs && knob_rank < 0; ++k)
      if (!same_knob(all[r], all[0], k)) knob_rank = r, knob = k;
  }
  if (config_rank < 0 && knob_rank < 0) return std::nullopt;

  Disagreement d;
  d.status = TESSERA_ERROR_CONFIG;
  if (config_rank >= 0) {
    // Both texts to every rank (bounded), so that every rank names the same line
    std::string ref = ctx.rank() == 0 ? effective_config.substr(0, kMaxConfigDiffBytes) : std::string();
    std::string theirs = ctx.rank() == config_rank ? effective_config.substr(0, kMaxConfigDiffBytes) : std::string();
    ctx.broadcast(ref, 0);
    ctx.broadcast(theirs, config_rank);
    std::string where = first_difference(theirs, ref);
    if (where.empty()) where = "the first " + std::to_string(kMaxConfigDiffBytes) + " bytes agree; they differ after";
    else where = "first difference at " + where;
    d.message = "ranks disagree on the config: " + rank_name(config_rank) +
                "'s effective config differs from rank 0's (" + where + ")";
  }
  if (knob_rank >= 0) {
    const std::string msg = std::string(kEnvironmentKnobs[knob]) + " is " + knob_value(all[knob_rank], knob) + " on " +
                            rank_name(knob_rank) + " but " + knob_value(all[0], knob) +
                            " on rank 0 (environment variables the library reads must be the same on every rank)";
    d.message += d.message.empty() ? "ranks disagree on the environment: " + msg : "; and " + msg;
  }
  return d;
}

std::string waiting_message(int rank, const CallView& call, double waited) {
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.0f", waited);
  CallRecord rec{};
  rec.kind = static_cast<std::uint64_t>(call.kind);
  rec.step = call.step;
  return rank_name(rank) + " has waited " + seconds + " s for the other ranks in the agreement of its call (it " +
         call_name(rec) +
         "): a rank that skipped this call, stopped calling the adapter without closing it, or is "
         "stuck leaves it waiting until that rank comes (no deadline; bound the job with the launcher, e.g. mpiexec "
         "--timeout)";
}

std::optional<Disagreement> agree_on_call(ParallelContext& ctx, const CallView& call, double warn_after,
                                          double* rank0_plan, int* pieced_axes) {
  const int n = ctx.size();
  if (rank0_plan) *rank0_plan = call.plan;
  if (pieced_axes) *pieced_axes = 0;
  if (n == 1) {
    if (pieced_axes && call.kind != CallKind::Close && call.domains_call && mesh_valid(call.mesh))
      *pieced_axes = call.mesh->axes_from_domains;
    return std::nullopt;
  }
  const CallRecord mine = call_record(call);
  std::vector<CallRecord> all(static_cast<std::size_t>(n));
  const int rank = ctx.rank();
  ctx.allgather_waiting(&mine, sizeof mine, all.data(), warn_after,
                        [&](double waited) { log_line(waiting_message(rank, call, waited)); });
  const CallRecord& ref = all[0];
  if (rank0_plan) *rank0_plan = std::bit_cast<double>(ref.plan_bits);

  // A rank that closes while another executes: nothing else in the records compares
  bool closed = false;
  for (int r = 0; r < n; ++r) closed = closed || all[r].kind == static_cast<std::uint64_t>(CallKind::Close);
  int other_call = -1;  // the first rank whose kind of call differs from rank 0's
  for (int r = 1; r < n && other_call < 0; ++r)
    if (all[r].kind != ref.kind) other_call = r;
  const auto call_disagreement = [&] {
    Disagreement d{TESSERA_ERROR_CONFIG,
                   "ranks disagree on the call: " + rank_name(other_call) + " " + call_name(all[other_call]) +
                       " while rank 0 " + call_name(ref) +
                       " (every rank must make the same calls: execute_final on every rank or on none, at the "
                       "same step, and close after the same calls)",
                   closed};
    if (closed) d.message += "; a rank has closed, so the others can only close this adapter now";
    return d;
  };
  if (other_call >= 0 && closed) return call_disagreement();
  if (ref.kind == static_cast<std::uint64_t>(CallKind::Close)) return std::nullopt;  // every rank closes

  // Step first (a different step explains different renders), then renders, then grid
  for (int r = 1; r < n; ++r)
    if (all[r].step != ref.step)
      return Disagreement{TESSERA_ERROR_DATA, "ranks disagree on the step: " + rank_name(r) + " is at step " +
                                                  std::to_string(all[r].step) + ", rank 0 at step " +
                                                  std::to_string(ref.step) +
                                                  " (every rank must call execute "
                                                  "with the same sequence of steps)"};
  for (int r = 1; r < n; ++r)
    if (!same_fired(all[r], ref))
      return Disagreement{TESSERA_ERROR_CONFIG, "ranks disagree on which renders fire at step " +
                                                    std::to_string(ref.step) + ": " +
                                                    fired_difference(all[r], ref, r, call)};
  // execute on one rank, execute_final on another, with the same renders firing
  if (other_call >= 0) return call_disagreement();
  // Grid or mesh, and the field lists: a difference is the same error on every rank
  std::vector<PublicationRecord> pubs(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) pubs[static_cast<std::size_t>(r)] = all[static_cast<std::size_t>(r)].pub;
  if (std::optional<std::string> diff =
          publication_disagreement(ctx, ref.step, pubs, PublicationView{call.mesh, call.domains, call.ndomains}))
    return Disagreement{TESSERA_ERROR_DATA, std::move(*diff)};
  bool grids = ref.pub.domains_call != 0;
  for (const PublicationRecord& rec : pubs) grids = grids && rec.has_grid;
  if (pieced_axes && grids) *pieced_axes = static_cast<int>(ref.pub.axes_from_domains);
  return std::nullopt;
}

}  // namespace tessera::insitu
