// An empty field descriptor (a zero extent, as a Fortran zero-size section or an empty
// simulation block gives) is reported as a zero-size array naming the field and the axis,
// whether its data pointer is NULL (what Fortran's c_loc leaves for it) or not; a NULL
// pointer with real extents is reported as a NULL pointer. Both are TESSERA_ERROR_DATA.
#include "insitu_test_support.h"

#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {

/// Status and message of one execute through the C API with the field changed by `edit`.
template <class Edit>
std::pair<tessera_status, std::string> execute_with(Edit&& edit) {
  TempDir dir;
  const std::string cfg = dir.write("a.yaml", config_yaml(dir.file("out"), render_yaml("r", "", "", "density", 8, 1)));
  tessera_adapter* a = nullptr;
  REQUIRE(tessera_open(cfg.c_str(), -1, &a) == TESSERA_OK);
  constexpr int n = 8;
  const std::vector<float> v = to_float(blob_values(n));
  tessera_field f = dense_field("density", v.data(), n);
  edit(f);
  const tessera_grid g = unit_grid(n);
  const tessera_status s = tessera_execute(a, 0, 0.0, &g, &f, 1);
  std::pair<tessera_status, std::string> out{s, tessera_last_error(a)};
  CHECK(tessera_close(a) == TESSERA_OK);
  return out;
}

}  // namespace

TEST_CASE("adapter: a zero-size field is named as one, not as a NULL pointer", "[robustness][insitu]") {
  for (int axis = 0; axis < 3; ++axis) {
    for (const bool null_data : {true, false}) {
      INFO("axis " << axis << (null_data ? ", NULL data" : ", data set"));
      const auto [status, error] = execute_with([&](tessera_field& f) {
        f.dims[axis] = 0;
        if (null_data) f.data = nullptr;
      });
      INFO(error);
      CHECK(status == TESSERA_ERROR_DATA);
      CHECK_THAT(error, Contains("field 'density': zero-size array: dims[" + std::to_string(axis) + "] (" +
                                 "ijk"[axis] + ") = 0"));
      CHECK_THAT(error, !Contains("null"));
    }
  }
  // A NULL pointer with extents: the pointer is the fault
  const auto [status, error] = execute_with([](tessera_field& f) { f.data = nullptr; });
  CHECK(status == TESSERA_ERROR_DATA);
  CHECK_THAT(error, Contains("field 'density': data pointer is null (dims 8x8x8)"));
  CHECK_THAT(error, !Contains("zero-size"));
}
