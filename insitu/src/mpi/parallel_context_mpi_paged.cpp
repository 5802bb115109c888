// MpiParallelContext, distributed mode: the global summary from per-rank partial summaries,
// the demand-paged field (every rank reads its own blocks in place, other bricks are fetched
// on first touch into a bounded cache) and the serving of bricks while kernels run (docs/mpi.md).
#include "mpi/mpi_check.h"
#include "mpi/parallel_context_mpi.h"

#include "data/block_ops.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

namespace tessera::insitu {
namespace {

using detail::check;

/// MPI_Allreduce in place over a long array, in pieces whose count fits an int.
template <class T>
void allreduce_long(T* data, std::size_t n, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  constexpr std::size_t kPiece = std::size_t{1} << 26;
  for (std::size_t at = 0; at < n; at += kPiece) {
    const int count = static_cast<int>(std::min(kPiece, n - at));
    check(MPI_Allreduce(MPI_IN_PLACE, data + at, count, type, op, comm), "MPI_Allreduce");
  }
}

/// How long the serving thread waits for a worker's request when nothing else is to do: short
/// enough that other ranks' requests are answered quickly, long enough not to spin.
constexpr std::chrono::microseconds kServeWait{100};

}  // namespace

std::shared_ptr<const FieldSummary> MpiParallelContext::summarize_blocks(std::span<const FieldBlock> blocks,
                                                                         const std::int64_t global[3], DType dtype,
                                                                         int edge) {
  FieldView primary;  // the block distribute_blocks reads in place (none: data null)
  primary.dtype = dtype;
  if (!blocks.empty()) primary = blocks[0].view;
  if (m_size == 1) return summarize_one_rank(blocks, global, dtype, edge);  // no MPI call
  check_boxes(blocks, global, dtype);
  // A rank whose blocks cannot be read (a device block's summary failing) still takes part in
  // the reduction, then fails (its caller's gate agrees on the failure): no rank is left
  // waiting in the collective
  FieldSummary::Parts parts = partial_of_blocks({}, global, edge);  // empty parts
  std::exception_ptr error;
  try {
    accumulate_blocks(parts, blocks, global, edge);
  } catch (...) {
    error = std::current_exception();
  }
  reduce_parts(parts);  // exact in any order: min / max / or / sum (field_summary.h)
  if (error) std::rethrow_exception(error);
  return FieldSummary::from_parts(std::move(parts), FieldLayout::of(primary), edge);
}

PagedField MpiParallelContext::distribute_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                                 DType dtype, int shift, std::size_t capacity) {
  if (m_size == 1) throw std::logic_error("distributed mode needs more than one rank");
  std::vector<int> counts;
  const std::vector<BlockRecord> all = check_boxes(blocks, global, dtype, &counts);
  return distribute_records(blocks, all, global, dtype, shift, capacity);
}

PagedField MpiParallelContext::distribute_amr(std::span<const FieldBlock> vblocks,
                                              std::span<const BlockRecord> vrecords, const std::int64_t vdims[3],
                                              DType dtype, int shift, std::size_t capacity) {
  if (m_size == 1) throw std::logic_error("distributed mode needs more than one rank");
  return distribute_records(vblocks, vrecords, vdims, dtype, shift, capacity);
}

void MpiParallelContext::reduce_parts(FieldSummary::Parts& parts) {
  if (m_size == 1) return;
  allreduce_long(parts.lo.data(), parts.lo.size(), MPI_DOUBLE, MPI_MIN, m_comm);
  allreduce_long(parts.hi.data(), parts.hi.size(), MPI_DOUBLE, MPI_MAX, m_comm);
  allreduce_long(parts.flags.data(), parts.flags.size(), MPI_UINT8_T, MPI_BOR, m_comm);
  std::uint64_t nan = parts.nan, elements = parts.elements;
  double vmin = parts.vmin, vmax = parts.vmax;
  check(MPI_Allreduce(&nan, &parts.nan, 1, MPI_UINT64_T, MPI_SUM, m_comm), "MPI_Allreduce");
  check(MPI_Allreduce(&elements, &parts.elements, 1, MPI_UINT64_T, MPI_SUM, m_comm), "MPI_Allreduce");
  check(MPI_Allreduce(&vmin, &parts.vmin, 1, MPI_DOUBLE, MPI_MIN, m_comm), "MPI_Allreduce");
  check(MPI_Allreduce(&vmax, &parts.vmax, 1, MPI_DOUBLE, MPI_MAX, m_comm), "MPI_Allreduce");
}

PagedField MpiParallelContext::distribute_records(std::span<const FieldBlock> blocks, std::span<const BlockRecord> all,
                                                  const std::int64_t global[3], DType dtype, int shift,
                                                  std::size_t capacity) {
  // No replica in this mode: give its memory back (collective over the node, like assemble)
  m_service.reset();
  free_replica();
  m_blocks.resize(all.size());
  for (std::size_t r = 0; r < all.size(); ++r) {
    for (int a = 0; a < 3; ++a) {
      m_blocks[r].offset[a] = all[r].offset[a];
      m_blocks[r].dims[a] = all[r].dims[a];
    }
    m_blocks[r].owner = all[r].rank;
  }
  m_paged_blocks.assign(blocks.begin(), blocks.end());
  const BrickGrid grid = BrickGrid::make(global, dtype, shift);
  const bool same = m_cache && m_cache->capacity() == capacity && m_cache->grid().shift == grid.shift &&
                    m_cache->grid().dtype == grid.dtype && std::equal(grid.dims, grid.dims + 3, m_cache->grid().dims);
  if (same) {
    m_cache->reset();  // the values may have changed since the last render
  } else {
    m_cache.reset();
    m_cache = std::make_unique<BrickCache>(grid, capacity);
  }
  // Every own block but the first (read in place through PagedField::local) is read in place
  // brick by brick wherever a brick lies wholly inside it; only straddling bricks are copied
  std::vector<InPlaceBlock> others;
  others.reserve(m_paged_blocks.empty() ? 0 : m_paged_blocks.size() - 1);
  for (std::size_t d = 1; d < m_paged_blocks.size(); ++d) {
    if (m_paged_blocks[d].on_device) continue;  // device memory: its bricks through slots
    InPlaceBlock& b = others.emplace_back();
    b.view = m_paged_blocks[d].view;
    for (int a = 0; a < 3; ++a) b.offset[a] = m_paged_blocks[d].offset[a];
  }
  m_cache->set_in_place(others);
  m_service = std::make_unique<BrickService>(m_comm, m_rank, m_blocks, m_paged_blocks, *m_cache);
  m_report.bricks = {};
  m_report.cache = {};
  m_report.cache_bytes = m_cache->allocated_bytes();

  PagedField f;
  f.dtype = dtype;
  for (int a = 0; a < 3; ++a) f.dims[a] = global[a];
  f.local.dtype = dtype;
  if (!m_paged_blocks.empty()) {
    f.local = m_paged_blocks[0].view;
    for (int a = 0; a < 3; ++a) f.offset[a] = m_paged_blocks[0].offset[a];
    if (m_paged_blocks[0].on_device) {  // a GPU reads it in place, the host through the cache
      f.local_device = f.local.data;
      f.local_device_only = true;
    }
  }
  f.cache = m_cache.get();
  return f;
}

void MpiParallelContext::end_distribution() {
  m_service.reset();
  m_cache.reset();
}

void MpiParallelContext::serve_during(const std::function<void()>& fn) {
  std::exception_ptr error;
  std::atomic<bool> done{false};
  // fn runs on its own thread (this one serves bricks) but as wide as the pass' arena
  // (tessera.threads, render_pass.cpp): a fresh arena of that width, not the caller's, whose
  // only reserved slot this serving thread holds
  tbb::task_arena arena(tbb::this_task_arena::max_concurrency());
  std::thread worker([&] {
    try {
      arena.execute(fn);
    } catch (...) {
      error = std::current_exception();
    }
    done.store(true, std::memory_order_release);
  });
  try {
    while (!done.load(std::memory_order_acquire)) m_service->progress(kServeWait);
  } catch (const std::exception& e) {
    m_cache->fail(std::string("serving bricks failed: ") + e.what());  // wakes fn's workers
    worker.join();
    throw;
  }
  worker.join();
  m_report.bricks = m_service->traffic();
  m_report.cache = m_cache->stats();
  if (error) std::rethrow_exception(error);
}

void MpiParallelContext::serve_while(const std::function<void()>& fn) {
  if (!m_service) {
    fn();
    return;
  }
  std::exception_ptr error;
  try {
    serve_during(fn);
  } catch (...) {
    error = std::current_exception();
  }
  // Every rank serves until every rank's fn has returned
  if (!error) {
    finish_serving();
    return;
  }
  m_service->drain();  // fn's error says more than the cache's failure it caused
  std::rethrow_exception(error);
}

void MpiParallelContext::finish_serving() {
  m_service->drain();
  if (m_cache->failed()) throw std::runtime_error(m_cache->failure());
}

}  // namespace tessera::insitu
