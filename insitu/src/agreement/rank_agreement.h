#pragma once
/// Ranks agree: the checks that keep ranks which were set up or called differently from
/// hanging in a collective or silently making a wrong image. Each check is ONE allgather of
/// a small fixed-size record (ParallelContext::allgather); every rank then compares every
/// rank's record with rank 0's and reaches the same verdict, so a disagreement is an error on
/// every rank naming the first rank that differs from rank 0 and the values.
///
///   at tessera_open (agree_on_open): the effective config (the canonical text of
///     config::to_yaml, output_dir override applied), hashed twice (hash64.h), and the raw
///     values of the environment variables the library reads (kEnvironmentKnobs). On a
///     config mismatch, rank 0 and the differing rank broadcast their texts (at most
///     kMaxConfigDiffBytes each, failure path only) so that the message names the first
///     differing line.
///   at each execute call where a render fires (agree_on_call), before any other collective:
///     the kind of call (execute or execute_final), the step, which renders fire, and the
///     global grid (origin, spacing, global_dims, doubles compared bit for bit), or with
///     tessera_execute_domains the mesh (the same, plus its association, levels and
///     rectilinear coordinates) and the field list of each rank's domains
///     (publication_agreement.h names the property, axis and index that differ). The same
///     record carries rank 0's render-budget plan (render_budget.h) to every rank: not
///     compared, adopted.
///   at close (agree_on_call with CallKind::Close): the same record, so that a rank still in
///     an execute call that fires meets the other ranks' close (and the reverse) and every
///     rank involved reports it instead of one of them waiting forever.
/// What is not compared here is checked later, also on every rank alike: the render's field
/// and per-rank descriptors (bind phase), dtypes, boxes, overlap and coverage of the global grid
/// (ParallelContext::assemble). Calls where nothing fires communicate nothing, so ranks must
/// make their execute calls with the same sequence of steps: with identical configs the
/// `every`/`at` triggers then decide identically. A rank that skips a call another rank
/// renders in is detected at its own next agreement (its next firing call, or its close),
/// which meets the other rank's record; a rank that never makes one again leaves the
/// others waiting.
#include "parallel/parallel_context.h"

#include <tessera/config/render_spec.h>
#include <tessera/tessera.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tessera::insitu {

/// Every environment variable the library reads (add new ones here): their raw values must
/// be the same on every rank.
inline constexpr std::array<const char*, 2> kEnvironmentKnobs = {"TESSERA_MPI_RANKS_PER_NODE", "TESSERA_TEST_CLOCK"};

/// A rank that has waited this long (seconds) in agree_on_call for the others says so on
/// stderr, and again each time the wait doubles (it keeps waiting: see agree_on_call).
inline constexpr double kAgreementWarnSeconds = 60.0;

/// At most this many bytes of each config text are exchanged to name the first differing line.
inline constexpr std::size_t kMaxConfigDiffBytes = std::size_t{1} << 20;

/// A disagreement: the status every rank returns and the message (the same on every rank).
struct Disagreement {
  tessera_status status = TESSERA_ERROR_CONFIG;
  std::string message;
  /// Some rank's record was a close: that rank has left the communicator, so no rank may
  /// enter another collective on it (every rank sees the same records: the same verdict).
  bool rank_closed = false;
};

/// Collective (one allgather; two broadcasts more on a config mismatch). effective_config:
/// this rank's config::to_yaml text. Reads the environment (kEnvironmentKnobs). Returns the
/// disagreement (status TESSERA_ERROR_CONFIG) or nothing. Throws only on MPI failure.
std::optional<Disagreement> agree_on_open(ParallelContext& ctx, const std::string& effective_config);

/// Which call a rank is in at an agreement (read as a number by every rank: keep the values).
enum class CallKind : unsigned char { Execute = 0, Final = 1, Close = 2 };

/// This rank's view of one execute call where a render fires, or of its close (kind Close:
/// step 0, fired empty, grid NULL).
struct CallView {
  CallKind kind = CallKind::Execute;
  std::int64_t step = 0;
  /// Per config render: 0 it does not fire, 1 it fires, 2 it fires if its `when` trigger
  /// does (decided later by an allreduce that every rank enters).
  std::span<const unsigned char> fired;
  /// The config's renders, for names in the message (same size as fired).
  std::span<const config::RenderSpec> renders;
  const tessera_grid* grid = nullptr;  ///< may be NULL (the bind phase reports it)
  /// This rank's render-budget plan for the call (budget_planner.h; 1 without a budget).
  /// Not compared: every rank renders with rank 0's (agree_on_call's `rank0_plan`).
  double plan = 1.0;
  /// tessera_execute_domains: the mesh instead of the grid (may be NULL or invalid: the bind
  /// phase reports it), and the domains, whose field lists (domain 0's on each rank) the ranks
  /// compare. What is compared and how a difference is named: publication_agreement.h.
  bool domains_call = false;
  /// tessera_execute_mesh_domains (curvilinear, unstructured): only the call's kind is
  /// compared here; the bind phase agrees on the field.
  bool mesh_call = false;
  const tessera_mesh* mesh = nullptr;
  const tessera_domain* domains = nullptr;
  std::int64_t ndomains = 0;
};

/// Collective (one allgather of a fixed-size record). Returns the disagreement (status
/// TESSERA_ERROR_CONFIG for the kind of call and the set of renders, TESSERA_ERROR_DATA for
/// step and grid) or nothing. A rank closing while another executes is found first ("ranks
/// disagree on the call: ..." naming the first rank that differs from rank 0 and both calls;
/// rank_closed set); then the step, the renders that fire, execute vs execute_final (the same
/// message), and the grid. Throws only on MPI failure. Not called where nothing fires.
/// A rank the others never join (one that skipped this call, stopped calling the adapter
/// without closing it, or is stuck) leaves this one waiting, with no deadline (a late rank
/// would complete an abandoned collective and go on alone); after warn_after seconds, and each
/// time the wait doubles, this rank logs waiting_message() (one line on stderr), so that the
/// hang is visible and names the call.
/// rank0_plan (may be NULL): receives rank 0's call.plan, bit for bit (this rank's own with
/// one rank), when the ranks agree.
/// pieced_axes (may be NULL): receives, when the ranks agree, the mesh's axes_from_domains
/// (the same on every rank), or 0 when some rank's mesh failed its own checks or the call
/// is no domains call.
std::optional<Disagreement> agree_on_call(ParallelContext& ctx, const CallView& call,
                                          double warn_after = kAgreementWarnSeconds, double* rank0_plan = nullptr,
                                          int* pieced_axes = nullptr);

/// The line a rank logs while it waits in agree_on_call (exposed for tests).
std::string waiting_message(int rank, const CallView& call, double waited);

/// The first differing line of two texts, as "line N: 'a' vs 'b'" (1-based, lines trimmed
/// and cut short); "" if equal. Exposed for tests.
std::string first_difference(const std::string& a, const std::string& b);

}  // namespace tessera::insitu
