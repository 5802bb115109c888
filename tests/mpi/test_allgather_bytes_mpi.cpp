// MpiParallelContext::allgather_bytes (insitu/src/mpi/parallel_context_mpi_setup.cpp): one
// MPI_Allgatherv after the sizes' allgather gives every rank every rank's piece, in rank order,
// byte for byte as the generic form of ParallelContext (a broadcast per rank) does; a total past
// the cap is std::length_error on every rank alike, with the generic form's message, and the
// context goes on working; allgatherv_plan's counts, displacements and INT_MAX refusal.
#include "mpi/parallel_context_mpi.h"

#include "mpi_test_support.h"

#include <catch2/catch.hpp>

#include <climits>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera::insitu::allgatherv_plan;
using tessera::insitu::AllgathervPlan;
using tessera::insitu::MpiParallelContext;
using tessera::insitu::ParallelContext;

namespace {

/// Rank r's piece: `length` bytes that name r and their position, NUL and 0xff bytes included.
std::string piece_of(int r, std::size_t length) {
  std::string s(length, '\0');
  for (std::size_t q = 0; q < length; ++q) s[q] = static_cast<char>((r * 131 + q * 7) % 256);
  return s;
}

/// What allgather_bytes threw on this rank ("" when it returned).
std::string refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::length_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("allgather_bytes: every rank's piece in rank order, as the generic form gives it", "[mpi][allgather]") {
  MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  const int r = ctx.rank(), n = ctx.size();
  // Uneven pieces, rank 0's empty; then every piece empty; then the last rank's piece alone
  for (int kind = 0; kind < 3; ++kind) {
    const auto length_of = [&](int q) -> std::size_t {
      return kind == 0 ? static_cast<std::size_t>(q) * 37 : kind == 2 && q == n - 1 ? 100000 : 0;
    };
    const std::string mine = piece_of(r, length_of(r));
    const std::vector<std::string> all = ctx.allgather_bytes(mine, 1u << 20);
    const std::vector<std::string> generic = ctx.ParallelContext::allgather_bytes(mine, 1u << 20);
    bool ok = all.size() == static_cast<std::size_t>(n) && all == generic;
    for (int q = 0; ok && q < n; ++q) ok = all[static_cast<std::size_t>(q)] == piece_of(q, length_of(q));
    INFO("rank " << r << ", pieces of kind " << kind);
    REQUIRE(all_ranks(ok));
  }
  // A context without MPI: its own piece
  MpiParallelContext alone;
  REQUIRE(alone.allgather_bytes("abc", 3) == std::vector<std::string>{"abc"});
}

TEST_CASE("allgather_bytes: a total past the cap is refused on every rank alike, and the context goes on",
          "[mpi][allgather][errors]") {
  MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  const int r = ctx.rank(), n = ctx.size();
  // Only the last rank's piece is large: every rank refuses, with the generic form's message
  const std::string mine = piece_of(r, r == n - 1 ? 5000 : 10);
  const std::size_t total = static_cast<std::size_t>(n - 1) * 10 + 5000;
  const std::string message = refusal([&] { ctx.allgather_bytes(mine, total - 1); });
  const std::string generic = refusal([&] { ctx.ParallelContext::allgather_bytes(mine, total - 1); });
  INFO("rank " << r << ": " << message);
  CHECK(message == generic);
  REQUIRE(all_ranks(message == "the ranks' pieces hold " + std::to_string(total) + " bytes, more than " +
                                   std::to_string(total - 1)));
  // At the cap exactly: every piece
  const std::vector<std::string> all = ctx.allgather_bytes(mine, total);
  REQUIRE(all_ranks(all.size() == static_cast<std::size_t>(n) && all[static_cast<std::size_t>(r)] == mine));
}

TEST_CASE("allgatherv_plan: int counts and displacements, totals past the cap or INT_MAX refused", "[allgather]") {
  const std::vector<std::uint64_t> sizes = {0, 5, 3, 0, 9};
  const AllgathervPlan plan = allgatherv_plan(sizes, 17);
  CHECK(plan.counts == std::vector<int>{0, 5, 3, 0, 9});
  CHECK(plan.displs == std::vector<int>{0, 0, 5, 8, 8});
  CHECK(plan.total == 17);
  CHECK_THROWS_WITH(allgatherv_plan(sizes, 16), "the ranks' pieces hold 17 bytes, more than 16");
  // One MPI_Allgatherv's counts are int: a smaller limit stands in for INT_MAX
  CHECK_THROWS_WITH(allgatherv_plan(sizes, 100, 16),
                    "the ranks' pieces hold 17 bytes, more than one MPI_Allgatherv carries (16)");
  const std::vector<std::uint64_t> big = {std::uint64_t{INT_MAX}, 1};
  CHECK_THROWS_WITH(allgatherv_plan(big, SIZE_MAX),
                    "the ranks' pieces hold 2147483648 bytes, more than one MPI_Allgatherv carries (2147483647)");
  // Sizes whose sum would wrap round: saturated, still refused
  const std::vector<std::uint64_t> wrap = {UINT64_MAX, 2};
  CHECK_THROWS_AS(allgatherv_plan(wrap, SIZE_MAX - 1), std::length_error);
}
