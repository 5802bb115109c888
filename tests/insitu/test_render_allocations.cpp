// A render allocates nothing proportional to the field: the adapter reads the simulation's
// array in place, with no copy, conversion or re-bricking. Every allocation of the process is
// counted while execute() runs: global operator new/delete are replaced, and so are malloc and
// friends (forwarding to glibc's __libc_* functions), which catches C libraries too. This
// file is its own test executable so that the counting allocator affects no other test.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/film.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <new>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

namespace {

std::atomic<bool> g_counting{false};
std::atomic<std::uint64_t> g_bytes{0}, g_calls{0}, g_largest{0};

void count(std::size_t n) {
  if (!g_counting.load(std::memory_order_relaxed)) return;
  g_bytes += n;
  ++g_calls;
  std::uint64_t prev = g_largest.load();
  while (n > prev && !g_largest.compare_exchange_weak(prev, n)) {
  }
}

void* counted_new(std::size_t n) {
  count(n);
  if (void* p = __libc_malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}

void* counted_new_aligned(std::size_t n, std::align_val_t a) {
  count(n);
  if (void* p = __libc_memalign(static_cast<std::size_t>(a), n ? n : 1)) return p;
  throw std::bad_alloc();
}

struct Counts {
  std::uint64_t bytes, calls, largest;
};

template <class Fn>
Counts measure(Fn&& fn) {
  g_bytes = 0;
  g_calls = 0;
  g_largest = 0;
  g_counting = true;
  fn();
  g_counting = false;
  return {g_bytes.load(), g_calls.load(), g_largest.load()};
}

}  // namespace

// The C allocator
extern "C" {
void* malloc(std::size_t n) {
  count(n);
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t s) {
  count(n * s);
  return __libc_calloc(n, s);
}
void* realloc(void* p, std::size_t n) {
  count(n);
  return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
void* memalign(std::size_t a, std::size_t n) {
  count(n);
  return __libc_memalign(a, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  count(n);
  return __libc_memalign(a, n);
}
int posix_memalign(void** out, std::size_t a, std::size_t n) {
  count(n);
  void* p = __libc_memalign(a, n);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
}

// The C++ allocator
void* operator new(std::size_t n) { return counted_new(n); }
void* operator new[](std::size_t n) { return counted_new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  count(n);
  return __libc_malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  count(n);
  return __libc_malloc(n ? n : 1);
}
void* operator new(std::size_t n, std::align_val_t a) { return counted_new_aligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted_new_aligned(n, a); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }

using namespace tessera::insitu;
using namespace tessera::insitu::test;

TEST_CASE("the counting allocator sees operator new and malloc", "[insitu][alloc]") {
  const Counts c = measure([] {
    delete new std::int64_t[1000];
    std::free(std::malloc(5000));
  });
  CHECK(c.bytes >= 13000);
  CHECK(c.calls >= 2);
}

TEST_CASE("a render allocates nothing proportional to the field", "[insitu][alloc]") {
  constexpr int n = 128;  // 128^3 float64: 16 MiB, so a copy would stand out
  constexpr int w = 32, h = 32;
  const std::size_t field_bytes = sizeof(double) * n * n * n;
  std::vector<double> sim(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) sim[i + n * (j + static_cast<std::size_t>(n) * k)] = ((i ^ j ^ k) & 15) * 10.0;
  tessera_field field = dense_field("density", nullptr, n);
  field.data = sim.data();
  field.dtype = TESSERA_FLOAT64;
  field.byte_strides[0] = 8;
  field.byte_strides[1] = 8LL * n;
  field.byte_strides[2] = 8LL * n * n;
  const tessera_grid grid = unit_grid(n);

  TempDir dir;
  const std::string extra = "    output: {file: \"{name}_{step:04d}\", formats: [exr, png]}\n";
  const std::string cfg =
      dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "{every: 2}", extra, "density", w, 1)));
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);

  // Film (double sums per pixel), the resolved image, EXR and PNG line buffers: a generous
  // multiple of the pixel count, independent of the field
  const std::size_t image_budget = static_cast<std::size_t>(w) * h * 512;
  const std::size_t limit = field_bytes / 8 + image_budget;
  for (std::int64_t step : {0, 2, 4}) {  // the first call includes one-time library setup
    tessera_status s = TESSERA_OK;
    const Counts c = measure([&] { s = adapter.execute(step, 0.0, grid, {&field, 1}); });
    REQUIRE(s == TESSERA_OK);
    INFO("step " << step << ": " << c.bytes << " bytes in " << c.calls << " allocations, largest " << c.largest
                 << "; limit " << limit << ", field " << field_bytes);
    CHECK(c.bytes < limit);
    CHECK(c.largest < field_bytes / 8);
  }

  // A call where nothing fires allocates nothing at all
  const Counts idle = measure([&] {
    for (std::int64_t step = 1; step < 100; step += 2) adapter.execute(step, 0.0, grid, {&field, 1});
  });
  CHECK(idle.calls == 0);
  CHECK(idle.bytes == 0);
}
