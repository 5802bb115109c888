// Triggers decide from the step alone, before any data is touched: a call where nothing fires
// (or a field no firing render uses) reads no field memory, even memory that cannot be read.
#include "insitu_test_support.h"
#include "outputs/triggers.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <sys/mman.h>
#include <unistd.h>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using tessera::config::TriggerSpec;

namespace {

/// Pages that fault on any access (PROT_NONE), unmapped at scope exit.
class NoAccessPages {
 public:
  explicit NoAccessPages(std::size_t bytes) : m_size(bytes) {
    m_ptr = ::mmap(nullptr, m_size, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    REQUIRE(m_ptr != MAP_FAILED);
  }
  ~NoAccessPages() { ::munmap(m_ptr, m_size); }
  const void* data() const { return m_ptr; }

 private:
  void* m_ptr;
  std::size_t m_size;
};

}  // namespace

TEST_CASE("Trigger: every, at, absent", "[insitu][triggers]") {
  TriggerSpec every;
  every.kind = TriggerSpec::Kind::Every;
  every.every = 4;
  const Trigger t(every);
  CHECK(t.fires_on_step(0));
  CHECK_FALSE(t.fires_on_step(3));
  CHECK(t.fires_on_step(8));
  CHECK(t.fires_on_step(-4));
  CHECK_FALSE(t.needs_field_max());

  TriggerSpec at;
  at.kind = TriggerSpec::Kind::At;
  at.at = {9, 2, 9, 5};
  const Trigger a(at);
  CHECK(a.fires_on_step(2));
  CHECK(a.fires_on_step(9));
  CHECK_FALSE(a.fires_on_step(3));

  const Trigger always(std::nullopt);
  CHECK(always.fires_on_step(17));

  TriggerSpec when;
  when.kind = TriggerSpec::Kind::When;
  when.above = 350.0;
  const Trigger w(when);
  CHECK(w.needs_field_max());
  CHECK(w.fires_on_max(350.5));
  CHECK_FALSE(w.fires_on_max(350.0));
}

TEST_CASE("a call where no trigger fires reads no field memory", "[insitu][triggers]") {
  TempDir dir;
  const std::string cfg = dir.write(
      "a.yaml", config_yaml(dir.file("out"), render_yaml("a", "{every: 5}") + render_yaml("b", "{at: [100]}")));
  const long page = ::sysconf(_SC_PAGESIZE);
  constexpr int n = 8;  // 8^3 float32 = 2 KiB: inside one page
  const NoAccessPages pages(static_cast<std::size_t>(page));
  const tessera_field field = dense_field("density", static_cast<const float*>(pages.data()), n);

  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  for (std::int64_t step = 1; step < 5; ++step) {
    CHECK(adapter.execute(step, 0.1 * step, unit_grid(n), {&field, 1}) == TESSERA_OK);
    CHECK(adapter.last_results().empty());
  }
  // The descriptors are not even looked at: a call that fires nothing accepts anything
  tessera_field broken{};
  broken.dtype = static_cast<tessera_dtype>(99);
  CHECK(adapter.execute(6, 0.6, tessera_grid{}, {&broken, 1}) == TESSERA_OK);
  CHECK(adapter.execute(7, 0.7, tessera_grid{}, {}) == TESSERA_OK);

  // The C API, too (the C++ adapter closed first: two open adapters may not share an output_dir)
  adapter.close();
  tessera_adapter* c = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &c) == TESSERA_OK);
  CHECK(tessera_execute(c, 3, 0.3, nullptr, &field, 1) == TESSERA_OK);
  CHECK(tessera_execute(c, 3, 0.3, nullptr, nullptr, 5) == TESSERA_OK);
  CHECK(std::string(tessera_last_error(c)).empty());
  tessera_close(c);
}

TEST_CASE("only fields used by a firing render are read", "[insitu][triggers]") {
  TempDir dir;
  const std::string renders =
      render_yaml("a", "{every: 1}", "", "density") + render_yaml("b", "{every: 2}", "", "pressure");
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), renders));
  constexpr int n = 8;
  const NoAccessPages pages(static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)));
  const std::vector<float> density = to_float(blob_values(n));
  const tessera_field fields[2] = {dense_field("density", density.data(), n),
                                   dense_field("pressure", static_cast<const float*>(pages.data()), n)};
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  CHECK(adapter.execute(1, 0.0, unit_grid(n), fields) == TESSERA_OK);
  REQUIRE(adapter.last_results().size() == 1);
  CHECK(adapter.last_results()[0].name == "a");
  CHECK(adapter.execute(3, 0.0, unit_grid(n), fields) == TESSERA_OK);
}
