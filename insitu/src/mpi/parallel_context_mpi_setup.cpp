// MpiParallelContext: construction in two steps (the communicator, then the nodes) and the
// byte collectives that the rank agreement uses in between (rank_agreement.h), and
// allgather_bytes (every rank's pieces in one MPI_Allgatherv). The rest of
// the context is in the other parallel_context_mpi*.cpp files (parallel_context_mpi.cpp lists them).
#include "mpi/mpi_check.h"
#include "mpi/parallel_context_mpi.h"

#include <tessera/message_text.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>

namespace tessera::insitu {
namespace {

using detail::check;

/// TESSERA_MPI_RANKS_PER_NODE (testing aid): group ranks into pretend nodes of that size.
/// The raw value is compared across ranks at open (rank_agreement.h) before this is read.
int ranks_per_node_from_env() {
  const char* s = std::getenv("TESSERA_MPI_RANKS_PER_NODE");
  if (!s) return 0;
  if (!*s)
    throw std::runtime_error("TESSERA_MPI_RANKS_PER_NODE is set but empty (allowed: an integer >= 0; "
                             "unset it for one replica per shared-memory node)");
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (*end != '\0' || v < 0 || v > INT_MAX)
    throw std::runtime_error("TESSERA_MPI_RANKS_PER_NODE='" + shown_value(s, 40) + "' must be an integer >= 0");
  return static_cast<int>(v);
}

}  // namespace

std::unique_ptr<ParallelContext> ParallelContext::create(int comm_f) {
  if (comm_f == -1) return std::make_unique<MpiParallelContext>();
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized)
    throw std::runtime_error("an MPI communicator was given (handle " + std::to_string(comm_f) + ") but MPI is " +
                             (finalized ? "finalized" : "not initialized"));
  const MPI_Comm comm = MPI_Comm_f2c(comm_f);
  bool bad = comm == MPI_COMM_NULL;
#if defined(OPEN_MPI)
  bad = bad || comm == nullptr;
#endif
  if (bad)
    throw std::runtime_error("MPI communicator handle " + std::to_string(comm_f) +
                             " is not a valid communicator (pass MPI_Comm_c2f(comm), or -1 for no MPI)");
  return std::make_unique<MpiParallelContext>(comm);  // connect() follows the agreement
}

MpiParallelContext::MpiParallelContext() = default;

MpiParallelContext::MpiParallelContext(MPI_Comm comm) : m_mpi(true) {
  check(MPI_Comm_dup(comm, &m_comm), "MPI_Comm_dup");
  MPI_Comm_set_errhandler(m_comm, MPI_ERRORS_RETURN);
  MPI_Comm_rank(m_comm, &m_rank);
  MPI_Comm_size(m_comm, &m_size);
}

MpiParallelContext::MpiParallelContext(MPI_Comm comm, int ranks_per_node) : MpiParallelContext(comm) {
  connect_nodes(ranks_per_node);
}

void MpiParallelContext::connect() {
  if (m_mpi) connect_nodes(ranks_per_node_from_env());
}

void MpiParallelContext::connect_nodes(int ranks_per_node) {
  if (m_connected) throw std::logic_error("MpiParallelContext: connected twice");
  m_connected = true;
  if (m_size == 1) return;  // one rank: nothing to share

  // Nodes: ranks that can map one replica; the node's rank 0 is its leader.
  if (ranks_per_node > 0) check(MPI_Comm_split(m_comm, m_rank / ranks_per_node, m_rank, &m_node), "MPI_Comm_split");
  else check(MPI_Comm_split_type(m_comm, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &m_node), "MPI_Comm_split_type");
  MPI_Comm_set_errhandler(m_node, MPI_ERRORS_RETURN);
  MPI_Comm_rank(m_node, &m_node_rank);
  MPI_Comm_size(m_node, &m_node_size);
  int leader = m_rank;
  check(MPI_Bcast(&leader, 1, MPI_INT, 0, m_node), "MPI_Bcast");
  m_leader_of.resize(m_size);
  check(MPI_Allgather(&leader, 1, MPI_INT, m_leader_of.data(), 1, MPI_INT, m_comm), "MPI_Allgather");
  m_node_count = 0;
  for (int r = 0; r < m_size; ++r) m_node_count += m_leader_of[r] == r ? 1 : 0;

  // The tile counter: one int64 on rank 0, in a passive-target epoch for the context's life.
  const MPI_Aint counter_bytes = m_rank == 0 ? sizeof(std::int64_t) : 0;
  check(MPI_Win_allocate(counter_bytes, sizeof(std::int64_t), MPI_INFO_NULL, m_comm, &m_counter, &m_counter_win),
        "MPI_Win_allocate");
  MPI_Win_set_errhandler(m_counter_win, MPI_ERRORS_RETURN);
  if (m_rank == 0) *m_counter = 0;
  check(MPI_Win_lock_all(0, m_counter_win), "MPI_Win_lock_all");
}

// ---------------------------------------------------------------------------------------
// Byte collectives (on the duplicated communicator; no connect() needed)

void MpiParallelContext::allgather(const void* mine, std::size_t bytes, void* all) {
  if (m_size == 1) {
    if (bytes > 0) std::memcpy(all, mine, bytes);
    return;
  }
  if (bytes > static_cast<std::size_t>(INT_MAX)) throw std::length_error("allgather: too many bytes");
  check(MPI_Allgather(mine, static_cast<int>(bytes), MPI_BYTE, all, static_cast<int>(bytes), MPI_BYTE, m_comm),
        "MPI_Allgather");
}

void MpiParallelContext::allgather_waiting(const void* mine, std::size_t bytes, void* all, double warn_after,
                                           const std::function<void(double)>& on_wait) {
  if (m_size == 1) return allgather(mine, bytes, all);  // (every rank of a larger one polls: no mixing)
  if (bytes > static_cast<std::size_t>(INT_MAX)) throw std::length_error("allgather: too many bytes");
  MPI_Request request = MPI_REQUEST_NULL;
  check(
      MPI_Iallgather(mine, static_cast<int>(bytes), MPI_BYTE, all, static_cast<int>(bytes), MPI_BYTE, m_comm, &request),
      "MPI_Iallgather");
  // Test back to back for the first millisecond (ranks that arrive together: as fast as a
  // blocking allgather), then with pauses of 50 us doubling to 1 ms, which leave the core to
  // the simulation or to oversubscribed ranks; on_wait at warn_after, 2x, 4x, ...
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  double next_warning = warn_after;
  std::chrono::microseconds pause(50);
  for (;;) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (done) return;
    const double waited = std::chrono::duration<double>(Clock::now() - start).count();
    if (warn_after > 0.0 && on_wait && waited >= next_warning) {
      try {
        on_wait(waited);
      } catch (...) {
      }
      next_warning *= 2.0;
    }
    if (waited < 1e-3) continue;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(1000));
  }
}

AllgathervPlan allgatherv_plan(std::span<const std::uint64_t> sizes, std::size_t max_total, std::uint64_t int_limit) {
  // The total, saturating (no size list can wrap it round to a small number)
  std::uint64_t total = 0;
  for (const std::uint64_t s : sizes) total = s > UINT64_MAX - total ? UINT64_MAX : total + s;
  if (total > max_total)
    throw std::length_error("the ranks' pieces hold " + std::to_string(total) + " bytes, more than " +
                            std::to_string(max_total));
  if (total > int_limit)
    throw std::length_error("the ranks' pieces hold " + std::to_string(total) +
                            " bytes, more than one MPI_Allgatherv carries (" + std::to_string(int_limit) + ")");
  AllgathervPlan plan;
  plan.total = static_cast<std::size_t>(total);
  int at = 0;
  for (const std::uint64_t s : sizes) {
    plan.counts.push_back(static_cast<int>(s));
    plan.displs.push_back(at);
    at += static_cast<int>(s);
  }
  return plan;
}

std::vector<std::string> MpiParallelContext::allgather_bytes(const std::string& mine, std::size_t max_total) {
  if (m_size == 1) return ParallelContext::allgather_bytes(mine, max_total);
  // Every rank's size, then the plan: the same on every rank, and so are its refusals
  const std::uint64_t size = mine.size();
  std::vector<std::uint64_t> sizes(static_cast<std::size_t>(m_size));
  allgather(&size, sizeof size, sizes.data());
  const AllgathervPlan plan = allgatherv_plan(sizes, max_total);
  // Every piece in one collective, then cut in rank order
  std::string gathered(plan.total, '\0');
  check(MPI_Allgatherv(mine.data(), plan.counts[static_cast<std::size_t>(m_rank)], MPI_BYTE, gathered.data(),
                       plan.counts.data(), plan.displs.data(), MPI_BYTE, m_comm),
        "MPI_Allgatherv");
  std::vector<std::string> all(sizes.size());
  for (std::size_t r = 0; r < all.size(); ++r)
    all[r] = gathered.substr(static_cast<std::size_t>(plan.displs[r]), static_cast<std::size_t>(plan.counts[r]));
  return all;
}

void MpiParallelContext::broadcast(std::string& text, int root) {
  if (m_size == 1) return;
  // Lengths past INT_MAX are cut (callers bound their texts far below)
  int len = m_rank == root ? static_cast<int>(std::min<std::size_t>(text.size(), INT_MAX)) : 0;
  check(MPI_Bcast(&len, 1, MPI_INT, root, m_comm), "MPI_Bcast");
  text.resize(static_cast<std::size_t>(len));
  if (len > 0) check(MPI_Bcast(text.data(), len, MPI_CHAR, root, m_comm), "MPI_Bcast");
}

}  // namespace tessera::insitu
