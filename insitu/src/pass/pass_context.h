#pragma once
/// What every phase of one render reads (PassContext: the render in its call, on this rank)
/// and the one place where the ranks agree after each phase (PhaseGate).
#include "parallel/parallel_context.h"
#include "pass/render_pass.h"

#include <tessera/config/config.h>
#include <tessera/render.h>
#include <tessera/tessera.h>

#include <chrono>
#include <string>
#include <utility>

namespace tessera::insitu {

using PassClock = std::chrono::steady_clock;

/// One render of one call on this rank: what its phases read (and the render's state and
/// the call's shared data, which some of them update).
struct PassContext {
  ParallelContext& ctx;
  const config::Config& cfg;
  const config::RenderSpec& spec;
  RenderState& render;             ///< kept between calls (last image, Cinema, log state)
  CallData& call;                  ///< shared by the call's renders (ranges, the assembled field)
  SummaryCache& summaries;         ///< the adapter's field summaries
  PassClock::time_point start;     ///< when this render began (its time limit counts from here)
  PassClock::time_point deadline;  ///< tessera.time_limit; max() = none
  int spp;                         ///< samples per pixel: the budget's plan, image.spp without one; 0 = skipped
  bool root() const { return ctx.rank() == 0; }
};

/// The agreement after a phase: the phase runs on this rank, then every rank learns whether
/// all succeeded (ParallelContext::agree), so that all take the same path and none is left
/// waiting in a collective. On any rank's failure the outcome records the status and a
/// message naming the render, the step and the rank (this rank's own fault, or that another
/// rank failed, quoting the first failing rank's message).
class PhaseGate {
 public:
  PhaseGate(const PassContext& pass, PassOutcome& out) : m_pass(pass), m_out(out) {}

  /// Runs fn, then agrees; false (and the outcome set) when some rank failed. A LayoutError on
  /// any rank (the ranks' boxes do not fit together) records TESSERA_ERROR_DATA instead of
  /// `status`, on every rank: a descriptor fault, whichever phase found it.
  template <class Fn>
  bool run(tessera_status status, Fn&& fn) {
    bool ok = true, layout = false;
    std::string fault;
    try {
      fn();
    } catch (const LayoutError& e) {
      ok = false;
      layout = true;
      fault = e.what();
    } catch (const std::exception& e) {
      ok = false;
      fault = e.what();
    } catch (...) {
      ok = false;
      fault = "unknown exception";
    }
    return settle(status, ok, layout, std::move(fault));
  }

 private:
  bool settle(tessera_status status, bool ok, bool layout, std::string fault);
  const PassContext& m_pass;
  PassOutcome& m_out;
};

/// Throws the time-limit failure: the limit, the time taken, the tiles finished.
[[noreturn]] void time_limit_passed(const PassContext& pass, const DeadlineExceeded& e);

}  // namespace tessera::insitu
