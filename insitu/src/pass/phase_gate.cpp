// The agreement after each phase of a render (pass_context.h).
#include "pass/pass_context.h"

#include <tessera/message_text.h>

#include <cstdio>
#include <limits>
#include <stdexcept>

namespace tessera::insitu {

bool PhaseGate::settle(tessera_status status, bool ok, bool layout, std::string fault) {
  ParallelContext& ctx = m_pass.ctx;
  if (ctx.agree(ok)) return true;
  // Rank 0 logs every failure; another rank only one of its own that rank 0 did not share.
  // Two extra reductions, on the failure path only: whether some rank's fault is a
  // LayoutError, and whether rank 0 failed
  const bool root = ctx.rank() == 0;
  const bool any_layout = ctx.any(layout);
  const bool root_failed = ctx.any(root && !ok);
  // The first failing rank's own message, for the others' (two more collectives)
  const int first_failed = ctx.min(ok ? std::numeric_limits<int>::max() : ctx.rank());
  std::string theirs = ok ? std::string() : fault;
  ctx.broadcast(theirs, first_failed);
  m_out.report_here = root || (!ok && !root_failed);
  m_out.result.status = any_layout ? TESSERA_ERROR_DATA : status;
  // A long output_dir is quoted short (each time), and nothing prints raw
  const std::string& dir = m_pass.cfg.global.output_dir;
  fault = message_quoting(std::move(fault), dir);
  std::string where = "render '" + m_pass.spec.name + "' at step " + std::to_string(m_pass.call.step) + ": ";
  if (ok)
    m_out.result.error = where + "failed on another rank (rank " + std::to_string(first_failed) + ": " +
                         message_quoting(std::move(theirs), dir) + ")";
  else if (ctx.size() > 1) m_out.result.error = where + "rank " + std::to_string(ctx.rank()) + ": " + fault;
  else m_out.result.error = where + fault;
  return false;
}

void time_limit_passed(const PassContext& pass, const DeadlineExceeded& e) {
  char buf[192];
  std::snprintf(buf, sizeof buf, "passed tessera.time_limit = %g s after %.2f s (%zu/%zu tiles done)",
                pass.cfg.global.time_limit, std::chrono::duration<double>(PassClock::now() - pass.start).count(),
                e.tiles_done(), e.tiles_total());
  throw std::runtime_error(buf);
}

}  // namespace tessera::insitu
