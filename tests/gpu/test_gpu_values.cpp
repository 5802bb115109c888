// Every field Value the device kernels hold against the CPU (docs/gpu.md): int16 (CT-like),
// uint8 and uint16 fields, cell-centred data, rectilinear axes, a hierarchy of two refinement
// levels, a vector's magnitude, curvilinear and unstructured meshes. Per Value: a block
// z-test between a CPU and a GPU render with their own seeds (36 blocks of 8x8 pixels, each |z| < 4.2: two-sided false-alarm
// probability 2.7e-5 per block, about 1e-3 per Value, Bonferroni), the same bits on two GPU
// runs and under a second CudaLaunch, and every path counter equal to the CPU's at the same
// seed. 48x48 pixels, 32 samples, fixed seeds.
#include "amr_hierarchy.h"
#include "gpu_test_util.h"
#include "warped_mesh.h"

#include <tessera/amr.h>
#include <tessera/cuda_render.h>
#include <tessera/magnitude_field.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

using namespace gpu_test;

namespace {

constexpr int kN = 32;

/// The heat field's values mapped by f into type T.
template <class T>
std::vector<T> mapped_field(int n, const std::function<double(double)>& f) {
  const std::vector<double> h = heat_field<double>(n);
  std::vector<T> v(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) v[i] = static_cast<T>(std::lround(f(h[i])));
  return v;
}

/// CPU (seed 11) against GPU (seed 12), then the GPU's bits on two runs and two launches.
void check_value(const char* what, const std::function<tessera::PreparedScene(std::uint64_t seed)>& prepare) {
  const tessera::PreparedScene cpu_scene = prepare(11);
  const tessera::PreparedScene gpu_scene = prepare(12);
  const tessera::Film cpu = render_cpu(cpu_scene);
  tessera::RenderStats st;
  tessera::CudaTransfer tr;
  const tessera::Film gpu = render_gpu(gpu_scene, {}, &tr, &st);
  const double z = max_block_z(cpu, gpu, 8);
  INFO(what << ": largest block |z| " << z << ", GPU samples " << st.samples << ", real collisions "
            << st.real_collisions << ", " << tr.bytes_to_device << " bytes to " << tr.device_name);
  CHECK(st.samples == static_cast<std::uint64_t>(48 * 48 * 32));
  CHECK(st.real_collisions > 0);
  CHECK(z < 4.2);
  const tessera::Film again = render_gpu(gpu_scene);
  tessera::CudaLaunch odd;
  odd.block_threads = 96;
  odd.samples_per_launch = 5;
  odd.pixels_per_launch = 700;
  const tessera::Film sliced = render_gpu(gpu_scene, odd);
  CHECK(same_bits(gpu, again));
  CHECK(same_bits(gpu, sliced));
  // The same paths as the CPU at the same seed: every counter equal (the GPU computes what
  // the CPU computes; a kernel that traced other paths, as the float32 instantiation once
  // did, differs here long before a z-test sees it)
  tessera::Film cpu_same(cpu_scene.desc().image.width, cpu_scene.desc().image.height);
  tessera::RenderStats cpu_st;
  tessera::render(cpu_scene, cpu_same, cpu_st);
  tessera::RenderStats gpu_st;
  const tessera::Film gpu_same = render_gpu(cpu_scene, {}, nullptr, &gpu_st);
#if defined(TESSERA_GPU_TESTS_EMULATED)
  // The host emulation computes with the CPU's compiler: every pixel's sums are the CPU's up
  // to the order of their additions (lanes), so to rounding
  CHECK(max_pixel_difference(cpu_same, gpu_same) < 1e-12);
#endif
  check_same_paths(gpu_st, cpu_st);
}

}  // namespace

TEST_CASE("GPU against CPU: an int16 CT-like field", "[gpu][values]") {
  // Hounsfield-like units: air -1000 to bone near 2000
  const auto field = mapped_field<std::int16_t>(kN, [](double t) { return (t - 300.0) * 3.0 - 1000.0; });
  check_value("int16", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.tf.lo = -1000.0;
    s.tf.hi = 2000.0;
    return tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Int16, kN, kN, kN), s);
  });
}

TEST_CASE("GPU against CPU: uint8 and uint16 fields", "[gpu][values]") {
  const auto u8 = mapped_field<std::uint8_t>(kN, [](double t) { return (t - 300.0) * 0.255; });
  check_value("uint8", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.tf.lo = 0.0;
    s.tf.hi = 255.0;
    return tessera::prepare(FieldView::contiguous(u8.data(), tessera::DType::UInt8, kN, kN, kN), s);
  });
  const auto u16 = mapped_field<std::uint16_t>(kN, [](double t) { return t * 40.0; });
  check_value("uint16", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.tf.lo = 300.0 * 40.0;
    s.tf.hi = 1300.0 * 40.0;
    return tessera::prepare(FieldView::contiguous(u16.data(), tessera::DType::UInt16, kN, kN, kN), s);
  });
}

TEST_CASE("GPU against CPU: cell-centred data", "[gpu][values]") {
  const std::vector<float> field = heat_field<float>(kN);
  check_value("float32 cells", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.geometry.association = tessera::Association::Cell;
    s.geometry.spacing = Vec3(1.0 / kN);
    return tessera::prepare(FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN), s);
  });
}

TEST_CASE("GPU against CPU: rectilinear axes", "[gpu][values]") {
  const std::vector<double> x = stretched(kN, 1.4), y = stretched(kN, 0.8), z = stretched(kN, 1.0);
  const std::vector<double> f64 = heat_field<double>(kN);
  check_value("rectilinear float64", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.geometry.coords[0] = x.data();
    s.geometry.coords[1] = y.data();
    s.geometry.coords[2] = z.data();
    return tessera::prepare(FieldView::contiguous(f64.data(), tessera::DType::Float64, kN, kN, kN), s);
  });
  // Cell data on one rectilinear axis (kN + 1 boundaries), int16 values
  const std::vector<double> xb = stretched(kN + 1, 1.3);
  const auto i16 = mapped_field<std::int16_t>(kN, [](double t) { return t; });
  check_value("rectilinear int16 cells", [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.geometry.association = tessera::Association::Cell;
    s.geometry.spacing = Vec3(1.0 / kN);
    s.geometry.coords[0] = xb.data();
    return tessera::prepare(FieldView::contiguous(i16.data(), tessera::DType::Int16, kN, kN, kN), s);
  });
}

// Two refinement levels against the CPU, on the device and in the host emulation; a CUDA build
// without their kernel (-DTESSERA_CUDA_AMR=OFF) refuses them by name (the CPU renders them)
TEST_CASE("GPU against CPU: two refinement levels (refused by a build without their kernel)", "[gpu][values]") {
  // Cell data: level 0 of 16^3 cells over the unit cube, level 1 (ratio 2) over the hot centre
  constexpr std::int64_t n0 = 16;
  const auto heat = [](const Vec3& p) {
    const double x = p.x - 0.55, y = p.y - 0.45, z = p.z - 0.5;
    return 300.0 + 900.0 * std::exp(-(x * x + y * y + z * z) / 0.03) + 80.0 * p.y;
  };
  const std::int64_t off0[3] = {0, 0, 0}, dims0[3] = {n0, n0, n0};
  const std::int64_t off1[3] = {8, 6, 8}, dims1[3] = {16, 18, 16};
  tessera_test::AmrHierarchy levels(dims0, tessera::Association::Cell, {2}, Vec3(0.0), Vec3(1.0 / n0));
  levels.add(0, off0, dims0, heat);
  levels.add(1, off1, dims1, heat);
  const tessera::AmrField& amr = levels.finish();
  const auto prepare = [&](std::uint64_t seed) {
    tessera::SceneDesc s = heat_scene(kN, seed);
    s.geometry.association = tessera::Association::Cell;
    s.geometry.spacing = Vec3(1.0 / n0);
    return tessera::prepare(amr, s, nullptr);
  };
#if defined(TESSERA_GPU_TESTS_EMULATED) || defined(TESSERA_CUDA_AMR)
  check_value("two refinement levels", prepare);
#else
  const tessera::PreparedScene ps = prepare(1);
  tessera::Film f(ps.desc().image.width, ps.desc().image.height);
  tessera::RenderStats st;
  CHECK_THROWS_WITH(gpu_render_tiles(ps, all_tiles(ps), f, st), Catch::Contains("refinement levels"));
#endif
}

TEST_CASE("GPU against CPU: a vector's magnitude", "[gpu][values]") {
  // Components (0.6 t, 0.8 t, 0) as float32, float64 and int16: |v| = t
  const std::vector<double> h = heat_field<double>(kN);
  std::vector<float> a(h.size());
  std::vector<double> b(h.size());
  std::vector<std::int16_t> c(h.size(), 0);
  for (std::size_t i = 0; i < h.size(); ++i) {
    a[i] = static_cast<float>(0.6 * h[i]);
    b[i] = 0.8 * h[i];
  }
  tessera::MagnitudeField m;
  m.components[0] = FieldView::contiguous(a.data(), tessera::DType::Float32, kN, kN, kN);
  m.components[1] = FieldView::contiguous(b.data(), tessera::DType::Float64, kN, kN, kN);
  m.components[2] = FieldView::contiguous(c.data(), tessera::DType::Int16, kN, kN, kN);
  check_value("magnitude", [&](std::uint64_t seed) { return tessera::prepare(m, heat_scene(kN, seed), nullptr); });
}

TEST_CASE("GPU against CPU: a curvilinear mesh", "[gpu][values][mesh]") {
  // One curvilinear domain of 20^3 warped vertices, float32 interleaved coordinates, float32
  // vertex values: trilinear in each hex's parametric coordinates (Newton's inverse)
  const std::vector<WarpedMeshPiece> pieces = {{20, 0, 19, MeshForm::Curvilinear, tessera::DType::Float32, false}};
  const tessera::Mesh mesh = mesh_of(pieces);
  check_value("curvilinear mesh", [&](std::uint64_t seed) { return tessera::prepare(mesh, heat_scene(20, seed)); });
}

TEST_CASE("GPU against CPU: unstructured hexes and tets in several domains", "[gpu][values][mesh]") {
  // Three domains along k: tets (int32 indices), hexes (int64), a curvilinear piece; float64
  // vertex values (barycentric on tets); then int16 cell data on tets
  constexpr int n = 16;
  const std::vector<WarpedMeshPiece> pieces = {{n, 0, 5, MeshForm::Tets, tessera::DType::Float64, false},
                                               {n, 5, 11, MeshForm::Hexes, tessera::DType::Float64, false, true},
                                               {n, 11, n - 1, MeshForm::Curvilinear, tessera::DType::Float64, false}};
  const tessera::Mesh mesh = mesh_of(pieces);
  check_value("hexes, tets and a curvilinear piece",
              [&](std::uint64_t seed) { return tessera::prepare(mesh, heat_scene(n, seed)); });
  const std::vector<WarpedMeshPiece> cells = {{n, 0, 8, MeshForm::Tets, tessera::DType::Int16, true, true},
                                              {n, 8, n - 1, MeshForm::Tets, tessera::DType::Int16, true}};
  const tessera::Mesh cell_mesh = mesh_of(cells);
  check_value("int16 cell data on tets",
              [&](std::uint64_t seed) { return tessera::prepare(cell_mesh, heat_scene(n, seed)); });
}
