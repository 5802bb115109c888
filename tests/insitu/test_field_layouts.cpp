// Fields are the simulation's memory: every layout and dtype the descriptors can express
// renders bit-identically to the same values in a dense float32 array.
#include "insitu_test_support.h"

#include <tessera/adapter.h>
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <limits>

using namespace tessera::insitu;
using namespace tessera::insitu::test;

namespace {

constexpr int kN = 14;

/// An array holding the test values in some layout, plus its descriptor.
struct Layout {
  std::vector<unsigned char> bytes;
  tessera_field field{};
};

template <class T>
void put(unsigned char* p, double v) {
  const T t = static_cast<T>(v);
  std::memcpy(p, &t, sizeof(T));
}

void put_value(tessera_dtype dt, unsigned char* p, double v) {
  switch (dt) {
    case TESSERA_UINT8: put<std::uint8_t>(p, v); break;
    case TESSERA_INT16: put<std::int16_t>(p, v); break;
    case TESSERA_UINT16: put<std::uint16_t>(p, v); break;
    case TESSERA_FLOAT32: put<float>(p, v); break;
    case TESSERA_FLOAT64: put<double>(p, v); break;
  }
}

std::size_t size_of(tessera_dtype dt) {
  switch (dt) {
    case TESSERA_UINT8: return 1;
    case TESSERA_INT16:
    case TESSERA_UINT16: return 2;
    case TESSERA_FLOAT32: return 4;
    default: return 8;
  }
}

/// The test values in an array of full_dims (ghosts included), element (i,j,k) at
/// origin_offset + i*s[0] + j*s[1] + k*s[2] bytes from the start of `bytes`. Ghost vertices
/// (and padding) hold `garbage`, which would change the image if it were ever read.
Layout make_layout(tessera_dtype dt, const std::int64_t full[3], const std::int64_t s[3], std::int64_t origin_offset,
                   std::size_t total_bytes, const std::int64_t glo[3], const std::int64_t ghi[3], double garbage) {
  const std::vector<double> v = blob_values(kN);
  Layout L;
  L.bytes.assign(total_bytes, 0);
  for (std::int64_t k = 0; k < full[2]; ++k)
    for (std::int64_t j = 0; j < full[1]; ++j)
      for (std::int64_t i = 0; i < full[0]; ++i) {
        const std::int64_t ri = i - glo[0], rj = j - glo[1], rk = k - glo[2];
        const bool real = ri >= 0 && rj >= 0 && rk >= 0 && ri < kN && rj < kN && rk < kN;
        const double value = real ? v[ri + kN * (rj + kN * rk)] : garbage;
        put_value(dt, L.bytes.data() + origin_offset + i * s[0] + j * s[1] + k * s[2], value);
      }
  tessera_field& f = L.field;
  f.name = "density";
  f.data = L.bytes.data() + origin_offset;
  f.dtype = dt;
  for (int a = 0; a < 3; ++a) {
    f.dims[a] = full[a];
    f.byte_strides[a] = s[a];
    f.ghosts_lo[a] = glo[a];
    f.ghosts_hi[a] = ghi[a];
  }
  return L;
}

Layout dense(tessera_dtype dt) {
  const std::int64_t e = static_cast<std::int64_t>(size_of(dt));
  const std::int64_t full[3] = {kN, kN, kN}, s[3] = {e, e * kN, e * kN * kN}, z[3] = {0, 0, 0};
  return make_layout(dt, full, s, 0, static_cast<std::size_t>(e) * kN * kN * kN, z, z, 0.0);
}

/// Renders `f` through a fresh adapter and returns the image (and the EXR path written).
tessera::Image render_field(const TempDir& dir, const std::string& tag, const tessera_field& f,
                            std::string* exr_path = nullptr) {
  const std::string cfg = dir.write(tag + ".yaml", config_yaml(dir.file("out_" + tag), render_yaml("r", "{every: 1}")));
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  const tessera_status s = adapter.execute(3, 0.25, unit_grid(kN), {&f, 1});
  INFO(adapter.last_error());
  REQUIRE(s == TESSERA_OK);
  if (exr_path) *exr_path = adapter.last_results().at(0).files.at(0);
  return *adapter.last_image("r");
}

}  // namespace

TEST_CASE("layouts and dtypes render bit-identically to a dense float32 array", "[insitu]") {
  TempDir dir;
  std::string reference_exr;
  const Layout ref = dense(TESSERA_FLOAT32);
  const tessera::Image reference = render_field(dir, "ref", ref.field, &reference_exr);
  REQUIRE(mean_luminance(reference) > 0.0);  // the blob shows

  SECTION("dtypes: float64, int16, uint16, uint8 (dense)") {
    for (const tessera_dtype dt : {TESSERA_FLOAT64, TESSERA_INT16, TESSERA_UINT16, TESSERA_UINT8}) {
      INFO("dtype " << dt);
      const Layout L = dense(dt);
      std::string exr;
      CHECK(same_pixels(render_field(dir, "dt" + std::to_string(dt), L.field, &exr), reference));
      // ... and the files written agree too
      CHECK(same_pixels(tessera::read_exr(exr), tessera::read_exr(reference_exr)));
    }
  }

  SECTION("ghost layers, different on every side, are skipped (they hold huge values)") {
    const std::int64_t glo[3] = {1, 2, 0}, ghi[3] = {2, 1, 3};
    const std::int64_t full[3] = {kN + 3, kN + 3, kN + 3};
    for (const tessera_dtype dt : {TESSERA_FLOAT32, TESSERA_FLOAT64, TESSERA_INT16}) {
      INFO("dtype " << dt);
      const std::int64_t e = static_cast<std::int64_t>(size_of(dt));
      const std::int64_t s[3] = {e, e * full[0], e * full[0] * full[1]};
      const double garbage = dt == TESSERA_INT16 ? 32767.0 : 1e30;
      const Layout L =
          make_layout(dt, full, s, 0, static_cast<std::size_t>(e * full[0] * full[1] * full[2]), glo, ghi, garbage);
      CHECK(same_pixels(render_field(dir, "ghost" + std::to_string(dt), L.field), reference));
    }
  }

  SECTION("strided: one component of an array of structs, padded rows and planes") {
    // struct {double pad; float value; float other;} = 16 bytes; rows padded by 3 structs
    const std::int64_t z[3] = {0, 0, 0}, full[3] = {kN, kN, kN};
    const std::int64_t row = 16 * (kN + 3), plane = row * (kN + 1) + 8;
    const std::int64_t s[3] = {16, row, plane};
    const Layout L = make_layout(TESSERA_FLOAT32, full, s, 8, static_cast<std::size_t>(plane * kN), z, z, 0.0);
    CHECK(same_pixels(render_field(dir, "aos", L.field), reference));
  }

  SECTION("transposed: C array a[i][j][k] (k fastest), float64") {
    const std::int64_t z[3] = {0, 0, 0}, full[3] = {kN, kN, kN};
    const std::int64_t s[3] = {8LL * kN * kN, 8LL * kN, 8};
    const Layout L = make_layout(TESSERA_FLOAT64, full, s, 0, 8u * kN * kN * kN, z, z, 0.0);
    CHECK(same_pixels(render_field(dir, "kfast", L.field), reference));
  }

  SECTION("Fortran array A(0:n+1, 0:n+1, 0:n+1) with one ghost layer, int16") {
    // Column-major: i fastest, leading dimension n+2
    const std::int64_t g[3] = {1, 1, 1}, full[3] = {kN + 2, kN + 2, kN + 2};
    const std::int64_t s[3] = {2, 2 * full[0], 2 * full[0] * full[1]};
    const Layout L = make_layout(TESSERA_INT16, full, s, 0, static_cast<std::size_t>(2 * full[0] * full[1] * full[2]),
                                 g, g, -32768.0);
    CHECK(same_pixels(render_field(dir, "fortran", L.field), reference));
  }

  SECTION("mirrored: negative strides along j and k") {
    const std::int64_t z[3] = {0, 0, 0}, full[3] = {kN, kN, kN};
    const std::int64_t s[3] = {4, -4LL * kN, -4LL * kN * kN};
    const std::int64_t first = 4LL * kN * kN * kN - 4LL * kN;  // element (0,0,0): last row
    const Layout L = make_layout(TESSERA_FLOAT32, full, s, first, 4u * kN * kN * kN, z, z, 0.0);
    CHECK(same_pixels(render_field(dir, "mirror", L.field), reference));
  }
}
