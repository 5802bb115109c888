// Tests for FieldView: every supported memory layout samples exactly like a contiguous copy,
// without copying, and validate() rejects impossible views naming the fault.
#include <tessera/field_view.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "sampling/rng.h"
#include "test_support.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using tessera::DType;
using tessera::FieldView;
using tessera::Vec3;
using tessera_test::dtype_of;
using tessera_test::make_medium;

namespace {

constexpr std::int64_t NX = 7, NY = 5, NZ = 6;

template <class T>
T random_value(tessera::Rng& rng) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(200.0 * rng.uniform() - 100.0);
  } else {
    const double lo = static_cast<double>(std::numeric_limits<T>::min());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    return static_cast<T>(lo + std::floor(rng.uniform() * (hi - lo + 1.0)));
  }
}

/// Logical value of vertex (i, j, k): the reference, stored i fastest.
template <class T>
std::vector<T> reference_values(std::uint64_t seed) {
  tessera::Rng rng(seed, 0, 0, 0);
  std::vector<T> v(NX * NY * NZ);
  for (T& x : v) x = random_value<T>(rng);
  return v;
}

inline std::size_t ref_index(std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<std::size_t>((k * NY + j) * NX + i);
}

/// Random voxel-space sample points: interior, on faces / edges / corners (coordinate exactly
/// 0 or n-1), on vertices, and a little outside the box (the medium clamps).
std::vector<Vec3> sample_points(const std::int64_t dims[3], int count, std::uint64_t seed) {
  tessera::Rng rng(seed, 1, 2, 3);
  std::vector<Vec3> pts;
  for (int s = 0; s < count; ++s) {
    Vec3 p;
    for (int a = 0; a < 3; ++a) {
      const double hi = static_cast<double>(dims[a] - 1);
      const double r = rng.uniform();
      const int kind = static_cast<int>(rng.uniform() * 5.0);
      if (kind == 0) p[a] = 0.0;
      else if (kind == 1) p[a] = hi;
      else if (kind == 2) p[a] = std::floor(rng.uniform() * (hi + 1.0));
      else if (kind == 3) p[a] = -0.5 + (hi + 1.0) * r;
      else p[a] = hi * r;
    }
    pts.push_back(p);
  }
  return pts;
}

/// Compare a view against the contiguous reference: every vertex loads the same value, and
/// the trilinear medium returns bit-identical values at many points.
template <class T>
void require_samples_like_reference(const FieldView& view, const std::vector<T>& ref) {
  REQUIRE(view.dtype == dtype_of<T>());
  REQUIRE(view.dims[0] == NX);
  REQUIRE(view.dims[1] == NY);
  REQUIRE(view.dims[2] == NZ);
  REQUIRE_NOTHROW(view.validate("view"));
  const FieldView copy = FieldView::contiguous(ref.data(), dtype_of<T>(), NX, NY, NZ);
  tessera::TransferFunction tf;
  tf.lo = -50.0;
  tf.hi = 50.0;
  const auto mv = make_medium<T>(view, tf);
  const auto mc = make_medium<T>(copy, tf);

  int vertex_mismatch = 0;
  const auto tv = tessera::typed<T>(view);
  for (std::int64_t k = 0; k < NZ; ++k)
    for (std::int64_t j = 0; j < NY; ++j)
      for (std::int64_t i = 0; i < NX; ++i)
        if (tv.load(i, j, k) != static_cast<double>(ref[ref_index(i, j, k)])) ++vertex_mismatch;
  CHECK(vertex_mismatch == 0);

  int value_mismatch = 0;
  for (const Vec3& p : sample_points(view.dims, 4000, 17)) {
    const double a = mv.value(p), b = mc.value(p);
    if (std::memcmp(&a, &b, sizeof(double)) != 0) ++value_mismatch;
  }
  CHECK(value_mismatch == 0);
}

/// Pointer identity: the view reads the caller's memory, so a write through the original
/// array is seen by the next load (no copy was made).
template <class T>
void require_no_copy(const FieldView& view, T* element_000) {
  CHECK(view.data == static_cast<const void*>(element_000));
  const auto tv = tessera::typed<T>(view);
  const T saved = *element_000;
  const T changed = static_cast<T>(saved == T(7) ? T(9) : T(7));
  *element_000 = changed;
  CHECK(tv.load(0, 0, 0) == static_cast<double>(changed));
  *element_000 = saved;
}

template <class T>
struct Rec {
  double before;
  T value;
  char tag;
};

}  // namespace

TEMPLATE_TEST_CASE("FieldView layouts sample exactly like a contiguous copy, without copying", "[field_view]",
                   std::uint8_t, std::int16_t, std::uint16_t, float, double) {
  using T = TestType;
  const DType dt = dtype_of<T>();
  const std::int64_t es = sizeof(T);
  const std::vector<T> ref = reference_values<T>(1234);

  SECTION("Fortran order: i fastest, a separate dense array") {
    std::vector<T> a(ref);
    const FieldView v = FieldView::contiguous(a.data(), dt, NX, NY, NZ);
    CHECK(v.byte_strides[0] == es);
    CHECK(v.byte_strides[1] == es * NX);
    CHECK(v.byte_strides[2] == es * NX * NY);
    require_samples_like_reference(v, ref);
    require_no_copy(v, a.data());
  }

  SECTION("C order: k fastest") {
    std::vector<T> a(ref.size());
    for (std::int64_t i = 0; i < NX; ++i)
      for (std::int64_t j = 0; j < NY; ++j)
        for (std::int64_t k = 0; k < NZ; ++k) a[(i * NY + j) * NZ + k] = ref[ref_index(i, j, k)];
    FieldView v;
    v.data = a.data();
    v.dtype = dt;
    v.dims[0] = NX, v.dims[1] = NY, v.dims[2] = NZ;
    v.byte_strides[0] = es * NY * NZ, v.byte_strides[1] = es * NZ, v.byte_strides[2] = es;
    require_samples_like_reference(v, ref);
    require_no_copy(v, a.data());
  }

  SECTION("strided: a sub-box of a larger array (k fastest)") {
    const std::int64_t BX = NX + 4, BY = NY + 3, BZ = NZ + 5, ox = 1, oy = 2, oz = 3;
    std::vector<T> big(BX * BY * BZ, T(0));
    auto bidx = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return (i * BY + j) * BZ + k; };
    for (std::int64_t i = 0; i < NX; ++i)
      for (std::int64_t j = 0; j < NY; ++j)
        for (std::int64_t k = 0; k < NZ; ++k) big[bidx(i + ox, j + oy, k + oz)] = ref[ref_index(i, j, k)];
    FieldView v;
    v.data = &big[bidx(ox, oy, oz)];
    v.dtype = dt;
    v.dims[0] = NX, v.dims[1] = NY, v.dims[2] = NZ;
    v.byte_strides[0] = es * BY * BZ, v.byte_strides[1] = es * BZ, v.byte_strides[2] = es;
    require_samples_like_reference(v, ref);
    require_no_copy(v, &big[bidx(ox, oy, oz)]);
  }

  SECTION("ghosted: FieldView::with_ghosts skips the ghost layers") {
    const std::int64_t lo[3] = {1, 2, 0}, hi[3] = {2, 1, 3};
    const std::int64_t full[3] = {NX + lo[0] + hi[0], NY + lo[1] + hi[1], NZ + lo[2] + hi[2]};
    // Ghost cells hold a poison value that must never be read.
    const T poison = std::numeric_limits<T>::max();
    std::vector<T> g(full[0] * full[1] * full[2], poison);
    auto gidx = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return (k * full[1] + j) * full[0] + i; };
    for (std::int64_t k = 0; k < NZ; ++k)
      for (std::int64_t j = 0; j < NY; ++j)
        for (std::int64_t i = 0; i < NX; ++i) g[gidx(i + lo[0], j + lo[1], k + lo[2])] = ref[ref_index(i, j, k)];
    const std::int64_t strides[3] = {es, es * full[0], es * full[0] * full[1]};
    const FieldView v = FieldView::with_ghosts(g.data(), dt, full, strides, lo, hi);
    require_samples_like_reference(v, ref);
    require_no_copy(v, &g[gidx(lo[0], lo[1], lo[2])]);
  }

  SECTION("array of structs: one component of a struct array") {
    std::vector<Rec<T>> recs(ref.size());
    for (std::size_t n = 0; n < ref.size(); ++n) recs[n] = Rec<T>{-1.0, ref[n], 'x'};
    const std::int64_t rs = sizeof(Rec<T>);
    FieldView v;
    v.data = &recs[0].value;
    v.dtype = dt;
    v.dims[0] = NX, v.dims[1] = NY, v.dims[2] = NZ;
    v.byte_strides[0] = rs, v.byte_strides[1] = rs * NX, v.byte_strides[2] = rs * NX * NY;
    require_samples_like_reference(v, ref);
    require_no_copy(v, &recs[0].value);
  }

  SECTION("mirrored: negative strides along i and k") {
    std::vector<T> m(ref.size());
    for (std::int64_t k = 0; k < NZ; ++k)
      for (std::int64_t j = 0; j < NY; ++j)
        for (std::int64_t i = 0; i < NX; ++i) m[ref_index(NX - 1 - i, j, NZ - 1 - k)] = ref[ref_index(i, j, k)];
    FieldView v;
    v.data = &m[ref_index(NX - 1, 0, NZ - 1)];
    v.dtype = dt;
    v.dims[0] = NX, v.dims[1] = NY, v.dims[2] = NZ;
    v.byte_strides[0] = -es, v.byte_strides[1] = es * NX, v.byte_strides[2] = -es * NX * NY;
    require_samples_like_reference(v, ref);
    require_no_copy(v, &m[ref_index(NX - 1, 0, NZ - 1)]);
  }
}

TEST_CASE("a strided and an array-of-structs view render bit-identically to a dense copy", "[field_view][render]") {
  // Field of 12 x 10 x 9 vertices, dense, i fastest.
  constexpr int X = 12, Y = 10, Z = 9;
  const std::vector<float> dense = tessera_test::blobby_field(X, Y, Z);

  tessera::SceneDesc scene;
  scene.geometry.spacing = Vec3(0.1);
  scene.tf.lo = 0.0;
  scene.tf.hi = 1.0;
  scene.tf.density_scale = 20.0;
  scene.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.3, 1.0});
  scene.camera.position = Vec3(0.55, 0.45, -2.0);
  scene.camera.look_at = Vec3(0.55, 0.45, 0.4);
  scene.camera.fov_deg = 35.0;
  scene.lights.push_back(tessera::SphereLightDesc{Vec3(2.0, 2.0, -1.0), 0.3, tessera::Color(5.0)});
  scene.background.color = tessera::Color(0.2);
  scene.integrator.macrocell = 4;
  scene.image = {12, 10, 2, 0.0};
  scene.options.seed = 99;

  auto render_image = [&](const FieldView& v, const tessera::TransferFunction& tf) {
    tessera::SceneDesc s = scene;
    s.tf = tf;
    const tessera::PreparedScene ps = tessera::prepare(v, s);
    return tessera_test::render_film(ps).resolve();
  };
  const tessera::Image want = render_image(FieldView::contiguous(dense.data(), DType::Float32, X, Y, Z), scene.tf);

  SECTION("sub-box of a larger float32 array, k fastest") {
    constexpr int BX = X + 3, BY = Y + 2, BZ = Z + 4;
    std::vector<float> big(BX * BY * BZ, std::numeric_limits<float>::quiet_NaN());
    for (int i = 0; i < X; ++i)
      for (int j = 0; j < Y; ++j)
        for (int k = 0; k < Z; ++k) big[((i + 2) * BY + (j + 1)) * BZ + (k + 3)] = dense[(k * Y + j) * X + i];
    FieldView v;
    v.data = &big[(2 * BY + 1) * BZ + 3];
    v.dtype = DType::Float32;
    v.dims[0] = X, v.dims[1] = Y, v.dims[2] = Z;
    v.byte_strides[0] = 4 * BY * BZ, v.byte_strides[1] = 4 * BZ, v.byte_strides[2] = 4;
    const tessera::Image got = render_image(v, scene.tf);
    REQUIRE(got.rgba.size() == want.rgba.size());
    CHECK(std::memcmp(got.rgba.data(), want.rgba.data(), want.rgba.size() * sizeof(float)) == 0);
  }

  SECTION("int16 component of a struct array vs a dense int16 copy") {
    // Quantise to int16 once; both views see the same integers.
    std::vector<std::int16_t> q(dense.size());
    for (std::size_t n = 0; n < dense.size(); ++n)
      q[n] = static_cast<std::int16_t>(std::lround(dense[n] * 30000.0 - 10000.0));
    struct Cell {
      float velocity[3];
      std::int16_t density;
      std::int16_t flags;
    };
    std::vector<Cell> cells(q.size());
    for (std::size_t n = 0; n < q.size(); ++n) cells[n] = Cell{{1.f, 2.f, 3.f}, q[n], -1};
    tessera::TransferFunction tf = scene.tf;
    tf.lo = -10000.0;
    tf.hi = 20000.0;
    const std::int64_t cs = sizeof(Cell);
    FieldView v;
    v.data = &cells[0].density;
    v.dtype = DType::Int16;
    v.dims[0] = X, v.dims[1] = Y, v.dims[2] = Z;
    v.byte_strides[0] = cs, v.byte_strides[1] = cs * X, v.byte_strides[2] = cs * X * Y;
    const tessera::Image a = render_image(v, tf);
    const tessera::Image b = render_image(FieldView::contiguous(q.data(), DType::Int16, X, Y, Z), tf);
    REQUIRE(a.rgba.size() == b.rgba.size());
    CHECK(std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0);
  }
}

TEST_CASE("FieldView::validate rejects impossible views with a message naming the fault", "[field_view]") {
  std::vector<float> buf(64, 0.0f);
  FieldView ok = FieldView::contiguous(buf.data(), DType::Float32, 4, 4, 4);
  REQUIRE_NOTHROW(ok.validate());

  SECTION("null data") {
    FieldView v = ok;
    v.data = nullptr;
    CHECK_THROWS_WITH(v.validate("density"), Catch::Contains("density") && Catch::Contains("null"));
  }
  SECTION("dims < 1 on each axis") {
    for (int a = 0; a < 3; ++a) {
      for (std::int64_t bad : {std::int64_t{0}, std::int64_t{-3}}) {
        FieldView v = ok;
        v.dims[a] = bad;
        CHECK_THROWS_WITH(v.validate("density"), Catch::Contains("density") &&
                                                     Catch::Contains("dims[" + std::to_string(a) + "]") &&
                                                     Catch::Contains(">= 1"));
      }
    }
  }
  SECTION("zero stride along an axis with more than one vertex") {
    FieldView v = ok;
    v.byte_strides[1] = 0;
    CHECK_THROWS_WITH(v.validate(), Catch::Contains("stride") && Catch::Contains("j"));
  }
  SECTION("overlapping strides: j steps inside the extent of i") {
    FieldView v = ok;
    v.byte_strides[1] = 8;  // i spans 4 * 4 = 16 bytes
    CHECK_THROWS_WITH(v.validate("density"), Catch::Contains("density") && Catch::Contains("overlap"));
  }
  SECTION("overlapping strides hidden by a negative sign") {
    FieldView v = ok;
    v.data = buf.data() + 3;
    v.byte_strides[0] = -4;
    v.byte_strides[1] = 4;
    CHECK_THROWS_WITH(v.validate(), Catch::Contains("overlap"));
  }
  SECTION("overlap between the slowest axes") {
    FieldView v = ok;
    v.byte_strides[2] = 4 * 4 * 3;  // j spans 4*4*3 + 16 bytes
    CHECK_THROWS_WITH(v.validate(), Catch::Contains("overlap") && Catch::Contains("k"));
  }
  SECTION("accepted: a single vertex along an axis with any stride, mirrored, interleaved") {
    FieldView v = ok;
    v.dims[2] = 1;
    v.byte_strides[2] = 0;
    CHECK_NOTHROW(v.validate());
    FieldView m = ok;
    m.data = buf.data() + 3;
    m.byte_strides[0] = -4;
    CHECK_NOTHROW(m.validate());
    // Two interleaved fields: stride 8 along i, each view touches every other float.
    FieldView s = FieldView::contiguous(buf.data() + 1, DType::Float32, 2, 4, 4);
    s.byte_strides[0] = 8, s.byte_strides[1] = 16, s.byte_strides[2] = 64;
    CHECK_NOTHROW(s.validate());
  }
  SECTION("with_ghosts leaving no real vertex") {
    const std::int64_t full[3] = {4, 4, 4}, strides[3] = {4, 16, 64};
    const std::int64_t lo[3] = {0, 2, 0}, hi[3] = {0, 2, 0};
    CHECK_THROWS_WITH(FieldView::with_ghosts(buf.data(), DType::Float32, full, strides, lo, hi),
                      Catch::Contains("ghost") && Catch::Contains("j"));
    const std::int64_t neg[3] = {-1, 0, 0};
    CHECK_THROWS_WITH(FieldView::with_ghosts(buf.data(), DType::Float32, full, strides, neg, hi),
                      Catch::Contains("negative"));
  }
  SECTION("prepare() validates the field too") {
    FieldView v = ok;
    v.dims[0] = 0;
    tessera::SceneDesc scene;
    scene.image = {4, 4, 1, 0.0};
    CHECK_THROWS_WITH(tessera::prepare(v, scene), Catch::Contains("dims[0]"));
  }
}

TEST_CASE("dtype sizes and names", "[field_view]") {
  CHECK(tessera::dtype_size(DType::UInt8) == 1);
  CHECK(tessera::dtype_size(DType::Int16) == 2);
  CHECK(tessera::dtype_size(DType::UInt16) == 2);
  CHECK(tessera::dtype_size(DType::Float32) == 4);
  CHECK(tessera::dtype_size(DType::Float64) == 8);
  CHECK(std::string(tessera::dtype_name(DType::Int16)) == "int16");
  CHECK(std::string(tessera::dtype_name(DType::Float64)) == "float64");
}
