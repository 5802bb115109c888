// unreadable_byte (tessera/host_readable.h): readable memory reads, an unmapped or no-access
// page is found at a probe inside it, the probes reach the span's last byte, and nothing
// faults.
#include <tessera/host_readable.h>

#include <sys/mman.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cstddef>
#include <vector>

TEST_CASE("unreadable_byte: readable spans read, unmapped and no-access pages are found", "[host_readable]") {
  const std::vector<double> heap(1000, 1.0);
  CHECK_FALSE(tessera::unreadable_byte(heap.data(), heap.size() * sizeof(double)));
  CHECK_FALSE(tessera::unreadable_byte(heap.data(), 1));
  CHECK_FALSE(tessera::unreadable_byte(nullptr, 0));  // nothing to read

  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  auto* m = static_cast<unsigned char*>(
      ::mmap(nullptr, 4 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
  REQUIRE(m != MAP_FAILED);
  // The last page without access: a span ending there is found in that page, one short of it reads
  REQUIRE(::mprotect(m + 3 * page, page, PROT_NONE) == 0);
  CHECK_FALSE(tessera::unreadable_byte(m, 3 * page));
  const auto bad = tessera::unreadable_byte(m, 3 * page + 1);  // only its last byte is out
  REQUIRE(bad);
  CHECK(*bad == 3 * page);
  const auto far = tessera::unreadable_byte(m + 5, 4 * page - 5);
  REQUIRE(far);
  CHECK(*far >= 3 * page - 5);
  CHECK(*far < 4 * page - 5);
  // Unmapped: found at the first probe
  REQUIRE(::munmap(m + 2 * page, 2 * page) == 0);
  const auto gone = tessera::unreadable_byte(m + 2 * page, 100);
  REQUIRE(gone);
  CHECK(*gone == 0);
  CHECK_FALSE(tessera::unreadable_byte(m, 2 * page));
  ::munmap(m, 2 * page);
}
