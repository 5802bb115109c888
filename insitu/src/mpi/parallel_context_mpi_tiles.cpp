// MpiParallelContext, tile scheduler: render(), with tiles handed out from a shared counter on
// rank 0 a few at a time (MPI_Fetch_and_op), each rank rendering its grabs into its own Film.
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"
#include "parallel/rank_threads.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <span>
#include <stdexcept>
#include <string>

namespace tessera::insitu {
namespace {

using detail::check;

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

void MpiParallelContext::render(const PreparedScene& scene, Film& film, RenderStats& stats) {
  m_report.render_bytes = 0;
  if (m_size > 1) {
    render_multi(scene, film, stats);
    return;
  }
  RenderStats local;
  const double cpu0 = process_cpu_seconds();
  tessera::render(scene, film, local);
  m_report.render_cpu_seconds = process_cpu_seconds() - cpu0;
  m_report.render_seconds = local.wall_seconds;
  m_report.tiles = static_cast<int>(scene.tiles().size());
  m_report.grabs = 1;
  m_report.chunk = m_report.tiles;
  stats.add_counters(local);
  stats.wall_seconds += local.wall_seconds;
  stats.threads = local.threads;
}

void MpiParallelContext::render_multi(const PreparedScene& scene, Film& film, RenderStats& stats) {
  detail::TypeList keep;
  const MPI_Datatype pixel = detail::pixel_type(keep);
  share_film(scene, film, pixel);
  RenderStats local;
  const std::vector<int> mine = render_grabbed_tiles(scene, film, local);
  gather_film(scene.tiles(), mine, scene.desc().image.width, pixel, film);
  reduce_stats(local, stats);
}

std::vector<int> MpiParallelContext::render_grabbed_tiles(const PreparedScene& scene, Film& film, RenderStats& local) {
  const int ntiles = static_cast<int>(scene.tiles().size());
  // Reset the counter; nobody grabs before the reset is visible.
  if (m_rank == 0) {
    const std::int64_t zero = 0;
    check(MPI_Accumulate(&zero, 1, MPI_INT64_T, 0, 0, 1, MPI_INT64_T, MPI_REPLACE, m_counter_win), "MPI_Accumulate");
    check(MPI_Win_flush(0, m_counter_win), "MPI_Win_flush");
  }
  check(MPI_Barrier(m_comm), "MPI_Barrier");

  // Threads: `threads: 0` means all hardware threads of the node, shared by its ranks
  // (rank_threads; the pass already runs in an arena of this width)
  const int threads = rank_threads(scene.desc().options.threads, m_node_size);
  tbb::task_arena arena(threads);  // render_tiles uses the arena's concurrency

  // Grab a few tiles at a time until none is left. A chunk keeps this rank's threads busy
  // without letting one rank take a large share at the end. On a GPU (every rank: the device
  // phase agreed) a grab's pixels go in one call of launches over all of them: about two grabs
  // per rank keep its thousands of threads busy and pay a call's fixed costs (copies, launch,
  // synchronisation) twice, not once per few tiles; the image does not depend on the split.
  const bool gpu = scene.desc().options.device == Device::Cuda;
  const int chunk = gpu ? std::max(1, (ntiles + 2 * m_size - 1) / (2 * m_size))
                        : std::clamp(ntiles / (8 * m_size), 1, std::max(4, 2 * threads));
  const std::int64_t step = chunk;
  std::vector<int> mine;
  mine.reserve(static_cast<std::size_t>(ntiles / m_size + chunk));
  std::string error;
  int grabs = 0;
  // tessera.time_limit: checked before each grab (and by render_tiles before each tile)
  const auto deadline = scene.desc().options.deadline;
  bool timed_out = false;
  std::int64_t tiles_done = 0;
  const auto grab_and_render = [&] {
    while (error.empty() && !timed_out) {
      if (std::chrono::steady_clock::now() >= deadline) {
        timed_out = true;
        return;
      }
      std::int64_t start = 0;
      check(MPI_Fetch_and_op(&step, &start, MPI_INT64_T, 0, 0, MPI_SUM, m_counter_win), "MPI_Fetch_and_op");
      check(MPI_Win_flush(0, m_counter_win), "MPI_Win_flush");
      if (start >= ntiles) return;
      const std::size_t first = mine.size();
      for (std::int64_t t = start; t < std::min<std::int64_t>(start + step, ntiles); ++t)
        mine.push_back(static_cast<int>(t));
      ++grabs;
      try {
        const std::span<const int> grabbed = std::span<const int>(mine).subspan(first);
        const auto run = [&] { arena.execute([&] { render_tiles(scene, grabbed, film, local); }); };
        // Distributed mode: the kernels run on another thread while this one serves bricks
        if (m_service) serve_during(run);
        else run();
        tiles_done += static_cast<std::int64_t>(grabbed.size());
      } catch (const DeadlineExceeded& e) {
        timed_out = true;
        tiles_done += static_cast<std::int64_t>(e.tiles_done());
      } catch (const std::exception& e) {
        error = "rank " + std::to_string(m_rank) + ": " + e.what();
      }
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_seconds();
  grab_and_render();  // MPI calls only from this thread (MPI_THREAD_FUNNELED)
  // Distributed mode: serve the other ranks until every rank has rendered its last tile
  if (m_service) {
    try {
      finish_serving();
    } catch (const std::exception& e) {
      if (error.empty()) error = "rank " + std::to_string(m_rank) + ": " + e.what();
    }
  }
  m_report.render_cpu_seconds = process_cpu_seconds() - cpu0;
  m_report.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m_report.tiles = static_cast<int>(mine.size());
  m_report.grabs = grabs;
  m_report.chunk = chunk;
  // One reduction, before the gather: ranks that failed, ranks cut short by the deadline and
  // the tiles finished, so every rank throws alike and none waits in the gather
  const std::int64_t mine_flags[3] = {error.empty() ? 0 : 1, timed_out ? 1 : 0, tiles_done};
  std::int64_t all_flags[3] = {};
  check(MPI_Allreduce(mine_flags, all_flags, 3, MPI_INT64_T, MPI_SUM, m_comm), "MPI_Allreduce");
  if (all_flags[0] > 0) throw std::runtime_error(error.empty() ? "rendering failed on another rank" : error);
  if (all_flags[1] > 0)
    throw DeadlineExceeded(static_cast<std::size_t>(all_flags[2]), static_cast<std::size_t>(ntiles));
  return mine;
}

}  // namespace tessera::insitu
