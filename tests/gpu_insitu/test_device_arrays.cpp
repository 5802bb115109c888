// Device arrays through the adapter (docs/gpu.md): a simulation's field in cudaMalloc'd memory
// is read in place on the GPU with `device: auto` (no field bytes copied, RenderResult.device
// "cuda:0") and its image agrees with the host array's CPU render within Monte Carlo error;
// `device: cpu` stages it to the host and renders exactly what the host array renders; the
// simulation's stream is waited for; a strided (ghost-layer) device view reads the right
// elements; a mesh's arrays in device memory are copied to the host (where its tables are
// built) and read in place by the GPU render with `device: auto`; a host mesh renders on the
// GPU with `device: cuda`.
#include "amr_patches.h"
#include "device_memory.h"
#include "insitu_test_support.h"
#include "mesh_blocks.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;

namespace {

constexpr int kN = 24;

/// A device copy of host values, freed at the end.
template <class T>
struct DeviceArray {
  T* ptr = nullptr;
  std::size_t n = 0;
  explicit DeviceArray(const std::vector<T>& host) : n(host.size()) {
    ptr = static_cast<T*>(device_test::alloc(n * sizeof(T)));
    device_test::upload(ptr, host.data(), n * sizeof(T));
  }
  ~DeviceArray() { device_test::release(ptr); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
};

std::string renders(int spp, double target_error = 0.0) {
  // Variance in the EXR for the z-test; 48x48 pixels
  std::string r = render_yaml("main", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr], variance: true}\n",
                              "density", 48, spp);
  if (target_error > 0.0) {
    const std::string spp_key = "spp: " + std::to_string(spp) + "}";
    r.replace(r.find(spp_key), spp_key.size(),
              "spp: " + std::to_string(spp) + ", target_error: " + std::to_string(target_error) + "}");
  }
  return r;
}

struct Rendered {
  tessera::Image image;
  RenderResult result;
};

Rendered render_once(const tessera_field& field, const tessera_grid& grid, const std::string& device, int spp,
                     void* stream = nullptr, double target_error = 0.0) {
  TempDir dir;
  Adapter adapter;
  const std::string cfg =
      dir.write("a.yaml", config_yaml(dir.file("out"), renders(spp, target_error), "  device: " + device + "\n"));
  adapter.set_quiet(true);
  REQUIRE(adapter.open(cfg) == TESSERA_OK);
  if (stream) REQUIRE(adapter.set_cuda_stream(stream) == TESSERA_OK);
  const tessera_status s = adapter.execute(1, 0.0, grid, {&field, 1});
  INFO(adapter.last_error());
  if (!adapter.last_results().empty()) INFO(adapter.last_results()[0].error);
  REQUIRE(s == TESSERA_OK);
  return {*adapter.last_image("main"), adapter.last_results().at(0)};
}

/// Block z-test of two images' luminance over 8x8 blocks, standard errors from each
/// render's per-pixel variance of the mean (the EXR's variance channel); the largest |z|.
double max_block_z(const tessera::Image& a, const tessera::Image& b) {
  REQUIRE(a.variance.size() == static_cast<std::size_t>(a.width) * a.height);
  REQUIRE(b.variance.size() == a.variance.size());
  const auto lum = [](const tessera::Image& im, int x, int y) {
    const float* p = im.px(x, y);
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  };
  const auto var = [](const tessera::Image& im, int x, int y) {
    return static_cast<double>(im.variance[static_cast<std::size_t>(y) * im.width + x]);
  };
  double worst = 0.0;
  for (int by = 0; by + 8 <= a.height; by += 8)
    for (int bx = 0; bx + 8 <= a.width; bx += 8) {
      double ma = 0, mb = 0, va = 0, vb = 0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) {
          ma += lum(a, x, y);
          mb += lum(b, x, y);
          va += var(a, x, y);
          vb += var(b, x, y);
        }
      const double se = std::sqrt(va + vb);
      if (se > 0) worst = std::max(worst, std::fabs(ma - mb) / se);
      else CHECK(ma == mb);
    }
  return worst;
}

}  // namespace

TEST_CASE("a device field is read in place on the GPU: no field bytes copied, CPU image within MC error",
          "[gpu][insitu]") {
  const std::vector<float> host = to_float(blob_values(kN));
  DeviceArray<float> dev(host);
  const tessera_field on_host = dense_field("density", host.data(), kN);
  const tessera_field on_device = dense_field("density", dev.ptr, kN);
  const Rendered cpu = render_once(on_host, unit_grid(kN), "cpu", 64);
  const Rendered gpu = render_once(on_device, unit_grid(kN), "auto", 64);
  CHECK(cpu.result.device == "cpu");
  CHECK_THAT(gpu.result.device, Contains("cuda:0"));
  // No field bytes: the same render over the host array copies exactly the field more
  const std::uint64_t field_bytes = host.size() * sizeof(float);
  const Rendered copied = render_once(on_host, unit_grid(kN), "cuda", 64);
  CHECK(copied.result.stats.bytes_to_device == gpu.result.stats.bytes_to_device + field_bytes);
  CHECK(copied.result.stats.bytes_to_host == gpu.result.stats.bytes_to_host);
  CHECK(same_pixels(copied.image, gpu.image));
  CHECK(gpu.result.field_passes == 1);  // the summary, made on the GPU
  CHECK(gpu.result.stats.samples == cpu.result.stats.samples);
  CHECK(max_block_z(cpu.image, gpu.image) < 4.2);
  // The same bits on every run
  const Rendered again = render_once(on_device, unit_grid(kN), "auto", 64);
  CHECK(same_pixels(gpu.image, again.image));
}

TEST_CASE("adaptive sampling on the GPU: the CPU's sample counts, its image within MC error", "[gpu][insitu]") {
  const std::vector<float> host = to_float(blob_values(kN));
  DeviceArray<float> dev(host);
  const Rendered cpu = render_once(dense_field("density", host.data(), kN), unit_grid(kN), "cpu", 64, nullptr, 0.05);
  const Rendered gpu = render_once(dense_field("density", dev.ptr, kN), unit_grid(kN), "auto", 64, nullptr, 0.05);
  CHECK(cpu.result.device == "cpu");
  CHECK_THAT(gpu.result.device, Contains("cuda:0"));
  INFO("samples " << gpu.result.stats.samples << " of " << 48 * 48 * 64);
  CHECK(gpu.result.stats.samples == cpu.result.stats.samples);
  CHECK(gpu.result.stats.samples < std::uint64_t{48 * 48 * 64});
  CHECK(max_block_z(cpu.image, gpu.image) < 4.2);
}

TEST_CASE("device: cpu stages a device field to the host and renders the host array's bits", "[gpu][insitu]") {
  const std::vector<float> host = to_float(blob_values(kN));
  DeviceArray<float> dev(host);
  const Rendered a = render_once(dense_field("density", host.data(), kN), unit_grid(kN), "cpu", 4);
  const Rendered b = render_once(dense_field("density", dev.ptr, kN), unit_grid(kN), "cpu", 4);
  CHECK(b.result.device == "cpu");
  CHECK(b.result.stats.bytes_to_host == host.size() * sizeof(float));
  CHECK(same_pixels(a.image, b.image));
}

TEST_CASE("device: cuda copies a host field to the GPU and says so", "[gpu][insitu]") {
  const std::vector<float> host = to_float(blob_values(kN));
  const Rendered r = render_once(dense_field("density", host.data(), kN), unit_grid(kN), "cuda", 4);
  CHECK_THAT(r.result.device, Contains("cuda:0"));
  CHECK(r.result.stats.bytes_to_device >= host.size() * sizeof(float));
}

TEST_CASE("a strided device view with ghost layers and the simulation's stream", "[gpu][insitu]") {
  // The field inside a (n+2)^3 float64 array with one ghost layer, filled on a stream
  const int m = kN + 2;
  const std::vector<double> inner = blob_values(kN);
  std::vector<double> padded(static_cast<std::size_t>(m) * m * m, -1e30);  // ghosts: never read
  for (int k = 0; k < kN; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i)
        padded[(i + 1) + m * ((j + 1) + static_cast<std::size_t>(m) * (k + 1))] =
            inner[i + kN * (j + static_cast<std::size_t>(kN) * k)];
  auto* dev = static_cast<double*>(device_test::alloc(padded.size() * sizeof(double)));
  void* stream = device_test::make_stream();
  device_test::upload(dev, padded.data(), padded.size() * sizeof(double), stream);
  tessera_field f{};
  f.name = "density";
  f.data = dev;
  f.dtype = TESSERA_FLOAT64;
  for (int a = 0; a < 3; ++a) {
    f.dims[a] = m;
    f.ghosts_lo[a] = 1;
    f.ghosts_hi[a] = 1;
  }
  f.byte_strides[0] = 8;
  f.byte_strides[1] = 8LL * m;
  f.byte_strides[2] = 8LL * m * m;
  const Rendered gpu = render_once(f, unit_grid(kN), "auto", 4, stream);
  tessera_field g = f;
  g.data = padded.data();
  const Rendered cpu_from_device = render_once(f, unit_grid(kN), "cpu", 4, stream);
  const Rendered cpu_from_host = render_once(g, unit_grid(kN), "cpu", 4);
  CHECK_THAT(gpu.result.device, Contains("cuda"));
  CHECK(same_pixels(cpu_from_device.image, cpu_from_host.image));
  device_test::destroy_stream(stream);
  device_test::release(dev);
}

#if defined(TESSERA_CUDA_AMR)
TEST_CASE("refinement levels through the adapter on the GPU: the CPU's image within MC error, the same bits each run",
          "[gpu][insitu][amr]") {
  // Three levels of cell data (ratios 2 and 4) in host patches, each level cut into slabs and
  // the patches listed out of order (tests/common/amr_patches.h): device cuda copies the
  // levels' replica and tables to the GPU and renders them there
  const tessera_test::Hierarchy h = tessera_test::hierarchy(3, TESSERA_CELL);
  const tessera_test::HeldPatches held(h.spec, h.many, tessera_test::blobs, 2);
  const std::vector<tessera_domain> domains = held.all(h.many_order);
  const tessera_mesh mesh = h.spec.mesh();
  const auto run = [&](const std::string& device) {
    TempDir dir;
    Adapter adapter;
    adapter.set_quiet(true);
    REQUIRE(adapter.open(dir.write(
                "a.yaml", config_yaml(dir.file("out"), renders(64), "  device: " + device + "\n"))) == TESSERA_OK);
    const tessera_status s = adapter.execute_domains(2, 0.0, mesh, domains);
    INFO(adapter.last_error());
    REQUIRE(s == TESSERA_OK);
    return Rendered{*adapter.last_image("main"), adapter.last_results().at(0)};
  };
  const Rendered cpu = run("cpu");
  const Rendered gpu = run("cuda");
  CHECK(cpu.result.device == "cpu");
  CHECK_THAT(gpu.result.device, Contains("cuda:0"));
  CHECK(gpu.result.stats.samples == cpu.result.stats.samples);
  CHECK(gpu.result.stats.bytes_to_device > 0);  // the levels' replica and tables
  CHECK(max_block_z(cpu.image, gpu.image) < 4.2);
  CHECK(same_pixels(gpu.image, run("cuda").image));
}
#endif

namespace {

/// One mesh execute of `domains` on `device` (`extra`: more global options); status and
/// error, the image and result when it rendered.
struct MeshRun {
  tessera_status status = TESSERA_OK;
  std::string error;
  std::optional<Rendered> rendered;
};
MeshRun execute_mesh(std::span<const tessera_mesh_domain> domains, const std::string& device,
                     const std::string& extra = "") {
  TempDir dir;
  Adapter ad;
  ad.set_quiet(true);
  const std::string r = render_yaml(
      "view", "", "    output: {file: \"{name}_{step:04d}\", formats: [exr], variance: true}\n", "f", 48, 32);
  REQUIRE(ad.open(dir.write("m.yaml", config_yaml(dir.file("out"), r, "  device: " + device + "\n" + extra))) ==
          TESSERA_OK);
  MeshRun run;
  run.status = ad.execute_mesh_domains(1, 0.0, domains);
  run.error = ad.last_error();
  if (run.status == TESSERA_OK) run.rendered = Rendered{*ad.last_image("view"), ad.last_results().at(0)};
  return run;
}

/// One mesh execute of two domains (unstructured hexes and tets) on `device`.
Rendered render_mesh_once(const std::string& device) {
  const std::int64_t n[3] = {12, 11, 13};
  tessera_test::MeshBlock lower(n, 0, 6), upper(n, 6, 12);
  const tessera_mesh_domain d[2] = {lower.domain(tessera_test::MeshBlock::Form::Hexes),
                                    upper.domain(tessera_test::MeshBlock::Form::Tets)};
  const MeshRun run = execute_mesh(d, device);
  INFO(run.error);
  REQUIRE(run.status == TESSERA_OK);
  return *run.rendered;
}

/// x, y, z interleaved (x0 y0 z0 x1 ...).
std::vector<double> interleaved(const tessera_test::MeshBlock& b) {
  std::vector<double> v;
  for (std::size_t i = 0; i < b.x.size(); ++i) v.insert(v.end(), {b.x[i], b.y[i], b.z[i]});
  return v;
}

}  // namespace

TEST_CASE("mesh arrays in device memory are copied to the host, and auto renders them on the GPU",
          "[gpu][insitu][mesh]") {
  const std::int64_t n[3] = {12, 11, 13};
  tessera_test::MeshBlock lower(n, 0, 6), upper(n, 6, 12);
  tessera_mesh_domain d[2] = {lower.domain(tessera_test::MeshBlock::Form::Curvilinear),
                              upper.domain(tessera_test::MeshBlock::Form::Tets)};
  const MeshRun host = execute_mesh(d, "cuda");
  INFO(host.error);
  REQUIRE(host.rendered);
  // The first domain's coordinates interleaved in one device array, the second's
  // connectivity and field in device memory
  const std::vector<double> xyz = interleaved(lower);
  DeviceArray<double> dev_xyz(xyz), dev_field(upper.vertex_values);
  DeviceArray<std::int32_t> dev_tets(upper.tets);
  d[0].coords.x = dev_xyz.ptr;
  d[0].coords.y = dev_xyz.ptr + 1;
  d[0].coords.z = dev_xyz.ptr + 2;
  d[0].coords.byte_stride = 3 * sizeof(double);
  d[1].connectivity = dev_tets.ptr;
  tessera_field f = d[1].fields[0];
  f.data = dev_field.ptr;
  d[1].fields = &f;
  const MeshRun dev = execute_mesh(d, "auto");
  INFO(dev.error);
  REQUIRE(dev.rendered);
  CHECK_THAT(dev.rendered->result.device, Contains("cuda:0"));
  // x, y and z copied as one span (beside the film's sums, which every GPU render brings
  // back); the render reads the device arrays where they are: the host mesh's render copies
  // exactly those bytes more to the device
  const std::uint64_t staged =
      (xyz.size() + upper.vertex_values.size()) * sizeof(double) + upper.tets.size() * sizeof(std::int32_t);
  CHECK(dev.rendered->result.stats.bytes_to_host == host.rendered->result.stats.bytes_to_host + staged);
  CHECK(dev.rendered->result.stats.bytes_to_device + staged == host.rendered->result.stats.bytes_to_device);
  CHECK(same_pixels(dev.rendered->image, host.rendered->image));
  // device: cpu renders the host copies on the CPU, the image within MC error
  const MeshRun cpu = execute_mesh(d, "cpu");
  REQUIRE(cpu.rendered);
  CHECK(cpu.rendered->result.device == "cpu");
  CHECK(cpu.rendered->result.stats.bytes_to_host == staged);
  CHECK(max_block_z(cpu.rendered->image, dev.rendered->image) < 4.2);
}

TEST_CASE("staging a mesh's device arrays over memory_limit_mb is refused before copying", "[gpu][insitu][mesh]") {
  const std::int64_t n[3] = {48, 48, 48};
  tessera_test::MeshBlock block(n, 0, 47);
  tessera_mesh_domain d = block.domain(tessera_test::MeshBlock::Form::Curvilinear);
  const std::vector<double> xyz = interleaved(block);  // 2.6 MiB
  DeviceArray<double> dev_xyz(xyz);
  d.coords.x = dev_xyz.ptr;
  d.coords.y = dev_xyz.ptr + 1;
  d.coords.z = dev_xyz.ptr + 2;
  d.coords.byte_stride = 3 * sizeof(double);
  const MeshRun run = execute_mesh({&d, 1}, "auto", "  memory_limit_mb: 1\n");
  CHECK(run.status == TESSERA_ERROR_RENDER);
  CHECK_THAT(run.error, Contains("copying the mesh's device arrays to the host needs 2.53 MiB") &&
                            Contains("tessera.memory_limit_mb = 1 MiB"));
}

TEST_CASE("device: cuda renders a mesh on the GPU from copies, auto keeps it on the CPU", "[gpu][insitu][mesh]") {
  const Rendered cpu = render_mesh_once("auto");
  const Rendered gpu = render_mesh_once("cuda");
  CHECK(cpu.result.device == "cpu");
  CHECK(cpu.result.stats.bytes_to_device == 0);
  CHECK_THAT(gpu.result.device, Contains("cuda:0"));
  // At least the coordinates, connectivity and values of both domains went to the device
  const std::uint64_t lower = 12 * 11 * 7, upper = 12 * 11 * 7;  // vertices of each domain
  const std::uint64_t cells = 11 * 10 * 6;                       // hexes of each domain
  const std::uint64_t arrays = (lower + upper) * 4 * sizeof(double) + cells * 8 * 4 + cells * 6 * 4 * 4;
  INFO("bytes to the device " << gpu.result.stats.bytes_to_device << ", the arrays " << arrays);
  CHECK(gpu.result.stats.bytes_to_device > arrays);
  CHECK(gpu.result.stats.samples == cpu.result.stats.samples);
  CHECK(gpu.result.stats.real_collisions > 0);
  CHECK(max_block_z(cpu.image, gpu.image) < 4.2);
  // The same bits on every run
  CHECK(same_pixels(gpu.image, render_mesh_once("cuda").image));
}

namespace {

/// One execute's status and error message with `tessera_extra` under tessera:.
std::pair<tessera_status, std::string> execute_once(const tessera_field& field, const tessera_grid& grid,
                                                    const std::string& tessera_extra) {
  TempDir dir;
  Adapter adapter;
  adapter.set_quiet(true);
  REQUIRE(adapter.open(dir.write("a.yaml", config_yaml(dir.file("out"), renders(4), tessera_extra))) == TESSERA_OK);
  const tessera_status s = adapter.execute(1, 0.0, grid, {&field, 1});
  return {s, adapter.last_error()};
}

}  // namespace

TEST_CASE("tessera.cuda_device past the visible devices fails by name", "[gpu][insitu]") {
  const std::vector<float> host = to_float(blob_values(kN));
  const auto [s, err] =
      execute_once(dense_field("density", host.data(), kN), unit_grid(kN), "  device: cuda\n  cuda_device: 4095\n");
  CHECK(s == TESSERA_ERROR_RENDER);
  CHECK_THAT(err, Contains("tessera.cuda_device is 4095, but") && Contains("visible (allowed: -1 or 0 to"));
}

TEST_CASE("staging a device field to the host over memory_limit_mb is refused before copying", "[gpu][insitu]") {
  // 2 MiB of float32 in device memory, rendered on the CPU (staged) under a 1 MiB limit
  constexpr int n = 81;
  const std::vector<float> host(static_cast<std::size_t>(n) * n * n, 1.0f);
  DeviceArray<float> dev(host);
  const auto [s, err] =
      execute_once(dense_field("density", dev.ptr, n), unit_grid(n), "  device: cpu\n  memory_limit_mb: 1\n");
  CHECK(s == TESSERA_ERROR_RENDER);
  CHECK_THAT(err, Contains("copying the field's device arrays to the host needs") && Contains("memory_limit_mb"));
}

TEST_CASE("a device mesh promised unchanged is read where it is: nothing copied to the host, the staged image's bits",
          "[gpu][insitu][mesh]") {
  const std::int64_t n[3] = {12, 11, 13};
  tessera_test::MeshBlock lower(n, 0, 6), upper(n, 6, 12);
  // Every array in device memory: the curvilinear domain's x, y, z interleaved in one array,
  // the tets' coordinates, connectivity and values apart
  const std::vector<double> xyz = interleaved(lower);
  DeviceArray<double> dev_xyz(xyz), lower_f(lower.vertex_values), ux(upper.x), uy(upper.y), uz(upper.z),
      upper_f(upper.vertex_values);
  DeviceArray<std::int32_t> dev_tets(upper.tets);
  tessera_mesh_domain d[2] = {lower.domain(tessera_test::MeshBlock::Form::Curvilinear),
                              upper.domain(tessera_test::MeshBlock::Form::Tets)};
  d[0].coords.x = dev_xyz.ptr;
  d[0].coords.y = dev_xyz.ptr + 1;
  d[0].coords.z = dev_xyz.ptr + 2;
  d[0].coords.byte_stride = 3 * sizeof(double);
  d[1].coords.x = ux.ptr;
  d[1].coords.y = uy.ptr;
  d[1].coords.z = uz.ptr;
  d[1].connectivity = dev_tets.ptr;
  tessera_field f[2] = {d[0].fields[0], d[1].fields[0]};
  f[0].data = lower_f.ptr;
  f[1].data = upper_f.ptr;
  d[0].fields = &f[0];
  d[1].fields = &f[1];
  // range: auto (the values' range read on the device too)
  const std::string tf = "    transfer_function: {range: auto, density_scale: {optical_depth: 10}, "
                         "opacity: [[0, 0], [1, 1]], diffuse: viridis}\n";
  const std::string r = render_yaml("view", "", tf, "f", 40, 8);
  TempDir dir;
  const auto open = [&](Adapter& ad, const std::string& name) {
    ad.set_quiet(true);
    REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(dir.file(name), r, "  device: auto\n"))) == TESSERA_OK);
  };
  Adapter ad;
  open(ad, "kept");
  REQUIRE(ad.execute_mesh_domains(1, 0.0, d) == TESSERA_OK);
  const RenderResult first = ad.last_results().at(0);
  CHECK_FALSE(first.mesh_layout_reused);
  // Step 2: new values on the device, the geometry promised unchanged
  for (double& v : lower.vertex_values) v = 1.5 * v + 0.25;
  for (double& v : upper.vertex_values) v = 1.5 * v + 0.25;
  device_test::upload(lower_f.ptr, lower.vertex_values.data(), lower.vertex_values.size() * sizeof(double));
  device_test::upload(upper_f.ptr, upper.vertex_values.data(), upper.vertex_values.size() * sizeof(double));
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(2, 0.1, d) == TESSERA_OK);
  const RenderResult resident = ad.last_results().at(0);
  const tessera::Image resident_image = *ad.last_image("view");
  CHECK(resident.mesh_layout_reused);
  CHECK_THAT(resident.device, Contains("cuda:0"));
  // Only the film's sums came back (as for any GPU render); the first call staged the mesh
  const std::uint64_t staged = (xyz.size() + lower.vertex_values.size() + upper.x.size() * 4) * sizeof(double) +
                               upper.tets.size() * sizeof(std::int32_t);
  CHECK(first.stats.bytes_to_host == resident.stats.bytes_to_host + staged);
  // The same step staged (a fresh adapter, no promise): the same bits
  Adapter fresh;
  open(fresh, "fresh");
  REQUIRE(fresh.execute_mesh_domains(2, 0.1, d) == TESSERA_OK);
  CHECK(fresh.last_results().at(0).stats.bytes_to_host == resident.stats.bytes_to_host + staged);
  CHECK(same_pixels(*fresh.last_image("view"), resident_image));
  // The lookup structure's tables stayed on the device with it: the resident call copied none
  // of them (the fresh adapter, building its own, copies them), the rest alike
  CHECK(resident.stats.bytes_to_device < first.stats.bytes_to_device);
  CHECK(fresh.last_results().at(0).stats.bytes_to_device == first.stats.bytes_to_device);
  // A broken promise that would read outside the arrays: refused by domain and element (its
  // words as on the host), TESSERA_ERROR_DATA, the GPU still usable
  std::vector<std::int32_t> tets = upper.tets;
  tets[4 * 17 + 2] = 1 << 24;
  device_test::upload(dev_tets.ptr, tets.data(), tets.size() * sizeof(std::int32_t));
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  CHECK(ad.execute_mesh_domains(3, 0.2, d) == TESSERA_ERROR_DATA);
  CHECK_THAT(ad.last_error(), Contains("mesh domain 1: element 17: vertex index 16777216 (entry 2) is outside"));
  device_test::upload(dev_tets.ptr, upper.tets.data(), upper.tets.size() * sizeof(std::int32_t));
  REQUIRE(ad.mesh_unchanged() == TESSERA_OK);
  REQUIRE(ad.execute_mesh_domains(4, 0.3, d) == TESSERA_OK);
  CHECK(ad.last_results().at(0).mesh_layout_reused);
  CHECK(ad.last_results().at(0).stats.bytes_to_host == resident.stats.bytes_to_host);
  CHECK(ad.last_results().at(0).stats.bytes_to_device == resident.stats.bytes_to_device);
  // No promise: the geometry hashed on the device is the one the layout was built over, so the
  // mesh stays where it is all the same; new values, the staged render's bits
  for (double& v : upper.vertex_values) v = 0.5 * v;
  device_test::upload(upper_f.ptr, upper.vertex_values.data(), upper.vertex_values.size() * sizeof(double));
  REQUIRE(ad.execute_mesh_domains(5, 0.4, d) == TESSERA_OK);
  CHECK(ad.last_results().at(0).mesh_layout_reused);
  CHECK(ad.last_results().at(0).stats.bytes_to_host == resident.stats.bytes_to_host);
  const tessera::Image found = *ad.last_image("view");
  Adapter fresh5;
  open(fresh5, "fresh5");
  REQUIRE(fresh5.execute_mesh_domains(5, 0.4, d) == TESSERA_OK);
  CHECK(same_pixels(*fresh5.last_image("view"), found));
  // A vertex moved on the device, no promise: staged and built again
  std::vector<double> moved_x = upper.x;
  moved_x[9] += 1e-3;
  device_test::upload(ux.ptr, moved_x.data(), moved_x.size() * sizeof(double));
  REQUIRE(ad.execute_mesh_domains(6, 0.5, d) == TESSERA_OK);
  CHECK_FALSE(ad.last_results().at(0).mesh_layout_reused);
  CHECK(ad.last_results().at(0).stats.bytes_to_host == resident.stats.bytes_to_host + staged);
}

TEST_CASE("one rank's domains in device memory are assembled on the device: nothing staged, the host's bits",
          "[gpu][insitu][domains]") {
  // The field cut into four slabs along k, each its own device array: with device auto the
  // adapter assembles them on the GPU (cuda_assemble_on_device) instead of staging them, so
  // the call copies to the host no more than the same domains on the host do (the film), and
  // the image is those domains' GPU image bit for bit (the same replica, built on the host
  // there); the range (range: auto) comes from the device blocks' summaries. A second call
  // assembles again (a new replica), with the same bits.
  const std::vector<float> host = to_float(blob_values(kN));
  const std::int64_t cuts[5] = {0, 5, 11, 18, kN};
  std::vector<std::vector<float>> slabs(4);
  std::vector<std::unique_ptr<DeviceArray<float>>> dev;
  std::vector<tessera_field> host_fields(4), dev_fields(4);
  std::vector<tessera_domain> host_domains(4), dev_domains(4);
  for (int d = 0; d < 4; ++d) {
    const std::int64_t nz = cuts[d + 1] - cuts[d];
    slabs[d].assign(host.begin() + cuts[d] * kN * kN, host.begin() + cuts[d + 1] * kN * kN);
    dev.push_back(std::make_unique<DeviceArray<float>>(slabs[d]));
    for (int on_device = 0; on_device < 2; ++on_device) {
      tessera_field& f = on_device ? dev_fields[d] : host_fields[d];
      f = dense_field("density", on_device ? dev[d]->ptr : slabs[d].data(), kN);
      f.dims[2] = nz;
      tessera_domain& dom = on_device ? dev_domains[d] : host_domains[d];
      dom = tessera_domain{};
      dom.offset[2] = cuts[d];
      dom.fields = &f;
      dom.nfields = 1;
    }
  }
  const tessera_grid g = unit_grid(kN);
  tessera_mesh mesh{};
  for (int a = 0; a < 3; ++a) {
    mesh.origin[a] = g.origin[a];
    mesh.spacing[a] = g.spacing[a];
    mesh.global_dims[a] = g.global_dims[a];
  }
  mesh.nlevels = 1;
  const auto run = [&](const std::vector<tessera_domain>& domains, const std::string& device) {
    TempDir dir;
    Adapter adapter;
    const std::string r = renders(16);  // range: auto
    adapter.set_quiet(true);
    REQUIRE(adapter.open(dir.write("a.yaml", config_yaml(dir.file("out"), r, "  device: " + device + "\n"))) ==
            TESSERA_OK);
    std::vector<Rendered> out;
    for (int step = 1; step <= 2; ++step) {
      const tessera_status s = adapter.execute_domains(step, 0.0, mesh, domains);
      INFO(adapter.last_error());
      REQUIRE(s == TESSERA_OK);
      out.push_back({*adapter.last_image("main"), adapter.last_results().at(0)});
    }
    return out;
  };
  const std::vector<Rendered> on_host = run(host_domains, "cuda");
  const std::vector<Rendered> on_device = run(dev_domains, "auto");
  // Slabs 0 and 2 on the host, 1 and 3 on the device: assembled on the device too, the host
  // slabs' elements (and nothing else more) copied there
  std::vector<tessera_domain> mixed = dev_domains;
  mixed[0] = host_domains[0];
  mixed[2] = host_domains[2];
  const std::uint64_t host_slabs = (slabs[0].size() + slabs[2].size()) * sizeof(float);
  const std::vector<Rendered> on_both = run(mixed, "auto");
  for (int c = 0; c < 2; ++c) {
    CHECK_THAT(on_device[c].result.device, Contains("cuda:0"));
    CHECK(on_device[c].result.stats.bytes_to_host == on_host[c].result.stats.bytes_to_host);
    CHECK(on_device[c].result.stats.bytes_to_device < on_host[c].result.stats.bytes_to_device);
    CHECK(same_pixels(on_host[c].image, on_device[c].image));
    CHECK_THAT(on_both[c].result.device, Contains("cuda:0"));
    CHECK(on_both[c].result.stats.bytes_to_host == on_host[c].result.stats.bytes_to_host);
    CHECK(on_both[c].result.stats.bytes_to_device == on_device[c].result.stats.bytes_to_device + host_slabs);
    CHECK(same_pixels(on_host[c].image, on_both[c].image));
  }
}
