// MpiParallelContext, statistics: every rank's render counters combined on rank 0.
#include "mpi/mpi_check.h"
#include "mpi/parallel_context_mpi.h"

#include <cstdint>
#include <iterator>

namespace tessera::insitu {

using detail::check;

void MpiParallelContext::reduce_stats(const RenderStats& local, RenderStats& stats) {
  // Packed by kRenderCounters: summed counters (and threads, the total over ranks, last) in
  // one reduction, kept-largest counters in another; wall time is the slowest rank's.
  constexpr std::size_t kCounters = std::size(kRenderCounters);
  std::uint64_t sum_in[kCounters + 1] = {}, sum_out[kCounters + 1] = {};
  std::uint64_t max_in[kCounters] = {}, max_out[kCounters] = {};
  for (std::size_t i = 0; i < kCounters; ++i) {
    const RenderCounter& c = kRenderCounters[i];
    (c.combine == RenderCounter::Combine::Sum ? sum_in : max_in)[i] = local.*c.field;
  }
  sum_in[kCounters] = static_cast<std::uint64_t>(local.threads);
  check(MPI_Reduce(sum_in, sum_out, kCounters + 1, MPI_UINT64_T, MPI_SUM, 0, m_comm), "MPI_Reduce");
  check(MPI_Reduce(max_in, max_out, kCounters, MPI_UINT64_T, MPI_MAX, 0, m_comm), "MPI_Reduce");
  double slowest = 0.0;
  check(MPI_Reduce(&m_report.render_seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, m_comm), "MPI_Reduce");

  // Rank 0 gets the totals; the others keep their own figures
  if (m_rank != 0) {
    stats.add_counters(local);
    stats.threads = local.threads;
    stats.wall_seconds += m_report.render_seconds;
    return;
  }
  RenderStats total;
  for (std::size_t i = 0; i < kCounters; ++i) {
    const RenderCounter& c = kRenderCounters[i];
    total.*c.field = c.combine == RenderCounter::Combine::Sum ? sum_out[i] : max_out[i];
  }
  stats.add_counters(total);
  stats.threads = static_cast<int>(sum_out[kCounters]);
  stats.wall_seconds += slowest;
}

}  // namespace tessera::insitu
