// A mesh whose arrays are device memory (Mesh::device; docs/gpu.md, "Meshes in device
// memory"): prepare checks its indices and summarises its values on the device over the
// layout of an earlier prepare of the same geometry, and the GPU renders it where it is. On
// a GPU (tessera_gpu_tests) the arrays are cudaMalloc'd copies and the device's kernels
// (cuda/mesh_device_cuda.cu) run; on the host emulation (every build) the host arrays are
// declared device memory and the host loops of the same per-item code run. Either way: the
// host prepare's summary and image bit for bit, and its faults by the same words.
#include "gpu_test_util.h"
#include "warped_mesh.h"

#include <tessera/mesh.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "cuda/mesh_device.h"
#include "mesh/mesh_summary.h"
#include "mesh/mesh_tables.h"

#if defined(TESSERA_GPU_TESTS_EMULATED)
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"
#else
#include <cuda_runtime_api.h>
#endif

#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace gpu_test;

namespace {

/// `m`'s arrays as device memory, read where they are (Mesh::device set): on a GPU, copies
/// (freed with the object); on the emulation, the host arrays declared device memory of an
/// emulated GPU installed for the object's life.
class DeviceMesh {
 public:
  explicit DeviceMesh(const tessera::Mesh& m) : mesh(m) {
    mesh.device = true;
#if defined(TESSERA_GPU_TESTS_EMULATED)
    tessera::cuda::EmulatedDevice dev;
    for (const tessera::MeshDomain& d : m.domains)
      for (int s = 0; s < tessera::kMeshArraySlots; ++s) {
        const tessera::MeshArraySpan a = tessera::mesh_array(d, static_cast<tessera::MeshArraySlot>(s));
        if (a.data) dev.device_ranges.emplace_back(a.data, static_cast<std::size_t>(a.bytes));
      }
    m_scope.emplace(tessera::cuda::emulated_backend(dev));
#else
    for (tessera::MeshDomain& d : mesh.domains)
      for (int s = 0; s < tessera::kMeshArraySlots; ++s) {
        const auto slot = static_cast<tessera::MeshArraySlot>(s);
        const tessera::MeshArraySpan a = tessera::mesh_array(d, slot);
        if (!a.data) continue;
        void* p = nullptr;
        REQUIRE(cudaMalloc(&p, static_cast<std::size_t>(a.bytes)) == cudaSuccess);
        m_owned.push_back(p);
        REQUIRE(cudaMemcpy(p, a.data, static_cast<std::size_t>(a.bytes), cudaMemcpyHostToDevice) == cudaSuccess);
        tessera::set_mesh_array(d, slot, p);
      }
#endif
  }
  ~DeviceMesh() {
#if !defined(TESSERA_GPU_TESTS_EMULATED)
    for (void* p : m_owned) cudaFree(p);
#endif
  }
  DeviceMesh(const DeviceMesh&) = delete;
  DeviceMesh& operator=(const DeviceMesh&) = delete;

  tessera::Mesh mesh;

 private:
#if defined(TESSERA_GPU_TESTS_EMULATED)
  std::optional<tessera::cuda::ScopedGpuEmulation> m_scope;
#else
  std::vector<void*> m_owned;
#endif
};

tessera::SceneDesc gpu_scene(int n, std::uint64_t seed) {
  tessera::SceneDesc s = heat_scene(n, seed);
  s.image = {24, 20, 4, 0.0};
  s.options.device = tessera::Device::Cuda;
  return s;
}

bool same_parts(const tessera::FieldSummary::Parts& a, const tessera::FieldSummary::Parts& b) {
  return a.lo.size() == b.lo.size() && std::memcmp(a.lo.data(), b.lo.data(), a.lo.size() * sizeof(double)) == 0 &&
         std::memcmp(a.hi.data(), b.hi.data(), a.hi.size() * sizeof(double)) == 0 && a.flags == b.flags;
}

/// The host's macrocells of `host` (its tables built on the host) for edge `edge`.
tessera::FieldSummary::Parts host_cells(const tessera::Mesh& host, int edge, tessera::MacroGrid* grid) {
  tessera::MeshTables t;
  t.build(host);
  *grid = tessera::macro_grid(t.geometry(), t.dims(), edge);
  const auto s = tessera::mesh_summary(t, edge);
  tessera::FieldSummary::Parts p;
  for (const tessera::CellRange& r : s->ranges()) {
    p.lo.push_back(r.lo);
    p.hi.push_back(r.hi);
    p.flags.push_back(static_cast<std::uint8_t>((r.nan ? 1 : 0) | (r.pos_inf ? 2 : 0) | (r.neg_inf ? 4 : 0)));
  }
  return p;
}

}  // namespace

TEST_CASE("GPU: a mesh in device memory is summarised on the device as the host does, and renders the same bits",
          "[gpu][mesh][device_mesh]") {
  struct Case {
    const char* name;
    std::vector<WarpedMeshPiece> pieces;
  };
  std::vector<Case> cases;
  cases.push_back({"curvilinear float32 + tets, vertex data", {}});
  cases.back().pieces.emplace_back(12, 0, 5, MeshForm::Curvilinear, tessera::DType::Float32, false);
  cases.back().pieces.emplace_back(12, 5, 11, MeshForm::Tets, tessera::DType::Float32, false, true);
  cases.push_back({"hexes uint16, cell data", {}});
  cases.back().pieces.emplace_back(12, 0, 11, MeshForm::Hexes, tessera::DType::UInt16, true);
  for (const Case& c : cases) {
    INFO(c.name);
    const tessera::Mesh host = mesh_of(c.pieces);
    const tessera::SceneDesc scene = gpu_scene(12, 5);
    const tessera::PreparedScene on_host = tessera::prepare(host, scene);
    const DeviceMesh dm(host);
    // The per-item passes against the host's tables
    for (const int edge : {1, 3, 8}) {
      tessera::MacroGrid g;
      const tessera::FieldSummary::Parts want = host_cells(host, edge, &g);
      CHECK(same_parts(tessera::cuda::mesh_summary_cells(dm.mesh, g, nullptr), want));
    }
    const tessera::cuda::MeshValueStats v = tessera::cuda::mesh_value_stats(dm.mesh, nullptr);
    const tessera::cuda::MeshValueStats hv = tessera::cuda::mesh_value_stats_host(host);
    CHECK(v.nan == hv.nan);
    CHECK(v.values == hv.values);
    CHECK(std::memcmp(&v.all.lo, &hv.all.lo, sizeof(double)) == 0);
    CHECK(std::memcmp(&v.all.hi, &hv.all.hi, sizeof(double)) == 0);
    CHECK(v.all.flags == hv.all.flags);
    CHECK(v.real.lo == hv.real.lo);
    CHECK(v.real.hi == hv.real.hi);
    const tessera::cuda::MeshIndexFault f = tessera::cuda::mesh_index_fault(dm.mesh, nullptr);
    CHECK(f.domain == -1);
    CHECK(f.real_cells == tessera::cuda::mesh_index_fault_host(host).real_cells);
    // prepare over the host's layout: the same image bit for bit
    const tessera::PreparedScene on_device = tessera::prepare(dm.mesh, scene, on_host.mesh_layout());
    CHECK(on_device.mesh_layout_reused());
    const tessera::Film want = render_gpu(on_host);
    CHECK(same_bits(render_gpu(on_device), want));
    // The device check's receipt: the value totals measured with it (the host's), covering
    // the device mesh only; prepare given it reads neither indices nor values again, and
    // renders the same bits
    const tessera::MeshChecked receipt = tessera::cuda_check_mesh_indices(dm.mesh);
    CHECK(receipt.covers(dm.mesh, false));
    CHECK_FALSE(receipt.covers(dm.mesh, true));
    CHECK_FALSE(receipt.covers(host, false));
    REQUIRE(receipt.values() != nullptr);
    const tessera::MeshValueTotals& t = *receipt.values();
    CHECK(t.values == hv.values);
    CHECK(t.nan == hv.nan);
    CHECK(std::memcmp(&t.lo, &hv.all.lo, sizeof(double)) == 0);
    CHECK(std::memcmp(&t.hi, &hv.all.hi, sizeof(double)) == 0);
    CHECK(t.real_lo == hv.real.lo);
    CHECK(t.real_hi == hv.real.hi);
    const tessera::PreparedScene taken = tessera::prepare(dm.mesh, scene, on_host.mesh_layout(), receipt);
    CHECK(same_bits(render_gpu(taken), want));
    // The geometry's hash on the device: the host's
    CHECK(tessera::cuda_mesh_geometry_hash(dm.mesh) == tessera::mesh_geometry_hash(host));
  }
}

TEST_CASE("GPU: a mesh in device memory: faults are named as on the host, nothing read outside the arrays",
          "[gpu][mesh][device_mesh]") {
  std::vector<WarpedMeshPiece> good = {{10, 0, 9, MeshForm::Hexes, tessera::DType::Float64, false}};
  const tessera::Mesh host = mesh_of(good);
  const tessera::SceneDesc scene = gpu_scene(10, 2);
  const tessera::PreparedScene first = tessera::prepare(host, scene);
  // Without a layout, or for the CPU: refused by name
  {
    const DeviceMesh dm(host);
    CHECK_THROWS_WITH(tessera::prepare(dm.mesh, scene), Catch::Contains("needs the layout of an earlier prepare"));
    tessera::SceneDesc cpu = scene;
    cpu.options.device = tessera::Device::Cpu;
    CHECK_THROWS_WITH(tessera::prepare(dm.mesh, cpu, first.mesh_layout()), Catch::Contains("renders on the GPU only"));
  }
  // An index out of range, and a vertex moved to NaN: check_mesh_indices' words for the host arrays
  const auto fault_of = [&](const tessera::Mesh& m) {
    try {
      tessera::check_mesh_indices(m);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  for (int which = 0; which < 2; ++which) {
    std::vector<WarpedMeshPiece> bad = {{10, 0, 9, MeshForm::Hexes, tessera::DType::Float64, false}};
    tessera::Mesh m = mesh_of(bad);
    if (which == 0) {
      auto* conn = static_cast<std::int32_t*>(const_cast<void*>(m.domains[0].connectivity));
      conn[8 * 41 + 6] = 1 << 20;
      conn[8 * 300 + 1] = -3;
    } else {
      auto* y = static_cast<double*>(const_cast<void*>(m.domains[0].coords.y));
      y[77] = std::nan("");
    }
    const std::string want = fault_of(m);
    REQUIRE_FALSE(want.empty());
    const DeviceMesh dm(m);
    CHECK_THROWS_WITH(tessera::prepare(dm.mesh, scene, first.mesh_layout()), want);
  }
  // A promise broken in the ghost field: a cell of the layout a ghost now, with an index that
  // the indices' check (real cells only) never sees. Refused before the render reads it; the
  // masks as built over are taken
  std::vector<WarpedMeshPiece> masked = {{10, 0, 9, MeshForm::Hexes, tessera::DType::Float64, false}};
  tessera::Mesh m = mesh_of(masked);
  const std::int64_t cells = m.domains[0].cell_count();
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(cells), 0);
  mask[300] = 1;  // a ghost from the start: left out of the layout
  m.domains[0].ghosts = {mask.data(), 1, cells};
  const tessera::PreparedScene built = tessera::prepare(m, scene);
  {
    const DeviceMesh dm(m);
    CHECK_NOTHROW(tessera::prepare(dm.mesh, scene, built.mesh_layout()));
  }
  mask[41] = 1;
  static_cast<std::int32_t*>(const_cast<void*>(m.domains[0].connectivity))[8 * 41 + 6] = 1 << 20;
  {
    const DeviceMesh dm(m);
    CHECK_THROWS_WITH(tessera::prepare(dm.mesh, scene, built.mesh_layout()),
                      Catch::Contains("the ghost fields are not those the layout was built over"));
  }
  // ... as on the host, where the element is named
  CHECK_THROWS_WITH(tessera::prepare(m, scene, built.mesh_layout()), Catch::Contains("element 41 is a ghost now"));
}

TEST_CASE("GPU: an unchanged host mesh's geometry stays on the device, only its values are copied again",
          "[gpu][mesh]") {
  // A reused layout keeps its tables and the host geometry's copy on the device: a later
  // prepare of the same geometry in other host arrays (a simulation's next buffers) renders
  // the same bits without reading them (overwritten after prepare), copying at least the
  // geometry's bytes fewer
  const std::vector<WarpedMeshPiece> pieces = {{14, 0, 7, MeshForm::Hexes, tessera::DType::Float64, false},
                                               {14, 7, 13, MeshForm::Tets, tessera::DType::Float32, false}};
  const tessera::Mesh mesh = mesh_of(pieces);
  const tessera::PreparedScene p1 = tessera::prepare(mesh, heat_scene(14, 5));
  tessera::CudaTransfer t1, t2;
  const tessera::Film a = render_gpu(p1, {}, &t1);
  std::vector<WarpedMeshPiece> twin = pieces;
  const tessera::Mesh twin_mesh = mesh_of(twin);
  const tessera::PreparedScene p2 = tessera::prepare(twin_mesh, heat_scene(14, 5), p1.mesh_layout());
  REQUIRE(p2.mesh_layout_reused());
  for (WarpedMeshPiece& p : twin) p.scribble_geometry();
  const tessera::Film b = render_gpu(p2, {}, &t2);
  CHECK(same_bits(a, b));
  INFO("bytes to the device: " << t1.bytes_to_device << ", then " << t2.bytes_to_device);
  CHECK(t2.bytes_to_device + geometry_bytes(mesh) < t1.bytes_to_device);
}
