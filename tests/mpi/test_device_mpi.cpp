// tessera.device under MPI, on the host emulation of a GPU (core/src/cuda/gpu_emulation.h, in
// every build): one "GPU" per rank renders the CPU's image; ranks that disagree (a rank with
// no GPU) under device: cuda fail together, naming why, and the next call renders; under
// device: auto the ranks agree on one device kind, so the image does not depend on which rank
// renders a tile (a rank without a GPU sends every rank to the CPU).
#include "mpi_test_support.h"

#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera::insitu::Adapter;

namespace {

constexpr int kN = 16;

/// This rank's slab (along k) of a blob on kN^3 vertices over the unit cube.
struct Slab {
  Slab() {
    const int r = world_rank(), n = world_size();
    k0 = kN * r / n;
    nk = kN * (r + 1) / n - k0;
    values.resize(static_cast<std::size_t>(kN) * kN * nk);
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i) {
          const double x = i / (kN - 1.0) - 0.5, y = j / (kN - 1.0) - 0.5, z = (k0 + k) / (kN - 1.0) - 0.5;
          values[i + kN * (j + static_cast<std::size_t>(kN) * k)] =
              static_cast<float>(250.0 * std::exp(-(x * x + y * y + z * z) / 0.08));
        }
    field.name = "density";
    field.data = values.data();
    field.dtype = TESSERA_FLOAT32;
    field.dims[0] = field.dims[1] = kN;
    field.dims[2] = nk;
    field.byte_strides[0] = 4;
    field.byte_strides[1] = 4LL * kN;
    field.byte_strides[2] = 4LL * kN * kN;
    for (int a = 0; a < 3; ++a) {
      grid.spacing[a] = 1.0 / (kN - 1);
      grid.global_dims[a] = kN;
    }
    grid.offset[2] = k0;
  }
  int k0 = 0, nk = 0;
  std::vector<float> values;
  tessera_field field{};
  tessera_grid grid{};
};

std::string config(const std::string& out, const std::string& device) {
  return "tessera:\n  output_dir: " + out + "\n  threads: 1\n  device: " + device +
         "\nrenders:\n"
         "  - name: view\n    field: density\n    trigger: {every: 1}\n"
         "    image: {width: 32, height: 32, spp: 8}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3}}, look_at: center, up: [0, 0, 1], "
         "fov: 40}\n"
         "    transfer_function: {range: [0, 250], density_scale: 40, opacity: [[0, 0], [1, 1]], diffuse: viridis}\n"
         "    lights: [{type: sphere, position: [3, -2, 3], radius: 0.4, intensity: 20}]\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

struct Run {
  tessera_status status = TESSERA_OK;
  std::string error, device;
  std::optional<tessera::Image> image;  // rank 0
};

/// One call of an adapter opened on `device` over this rank's slab (`data`: the slab's values
/// or another copy of them).
Run run(const SharedTempDir& dir, const std::string& tag, const std::string& device, const void* data = nullptr) {
  Slab slab;
  if (data) slab.field.data = data;
  Adapter a;
  a.set_quiet(true);
  const std::string cfg = dir.write(tag + ".yaml", config(dir.file(tag), device));
  REQUIRE(all_ranks(a.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
  Run r;
  r.status = a.execute(1, 0.0, slab.grid, {&slab.field, 1});
  r.error = a.last_error();
  if (!a.last_results().empty()) r.device = a.last_results()[0].device;
  if (const tessera::Image* im = a.last_image("view")) r.image = *im;
  return r;
}

/// The largest difference between two images' RGBA relative to max(1, |value|).
double max_difference(const tessera::Image& a, const tessera::Image& b) {
  if (a.rgba.size() != b.rgba.size()) return 1.0;
  double d = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i)
    d = std::fmax(d, std::fabs(a.rgba[i] - b.rgba[i]) / std::fmax(1.0, std::fabs(a.rgba[i])));
  return d;
}

}  // namespace

TEST_CASE("device: cuda on every rank's GPU renders the CPU's image", "[mpi][gpu]") {
  SharedTempDir dir("tessera_device_");
  const Run cpu = run(dir, "cpu", "cpu");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const Run dev = run(dir, "cuda", "cuda");
  CHECK(all_ranks(cpu.status == TESSERA_OK));
  CHECK(all_ranks(dev.status == TESSERA_OK));
  CHECK(all_ranks(dev.device == "cuda:0"));
  if (world_rank() == 0) {
    REQUIRE(cpu.image);
    REQUIRE(dev.image);
    // The same samples summed in another order: equal to float rounding
    CHECK(max_difference(*cpu.image, *dev.image) < 1e-5);
  }
}

TEST_CASE("device: cuda with a rank that has no GPU fails on every rank, and the next call renders", "[mpi][gpu]") {
  if (world_size() < 2) return;  // needs a rank without the GPU
  SharedTempDir dir("tessera_device_");
  std::optional<tessera::cuda::ScopedGpuEmulation> gpu;
  if (world_rank() == 0) gpu.emplace(tessera::cuda::emulated_backend());
  const Run dev = run(dir, "cuda", "cuda");
  INFO(dev.error);
  CHECK(all_ranks(dev.status == TESSERA_ERROR_RENDER));
  CHECK(all_ranks(dev.error.find("tessera.device is cuda, but") != std::string::npos));
  const Run cpu = run(dir, "cpu", "cpu");
  CHECK(all_ranks(cpu.status == TESSERA_OK));
}

TEST_CASE("device: auto with device memory on some ranks only: every rank on the CPU", "[mpi][gpu]") {
  if (world_size() < 2) return;
  SharedTempDir dir("tessera_device_");
  const Run cpu = run(dir, "cpu", "cpu");
  // Rank 0: a GPU, and its slab in (emulated) device memory; the others: no GPU
  std::optional<tessera::cuda::ScopedGpuEmulation> gpu;
  std::vector<float> on_device;
  if (world_rank() == 0) {
    gpu.emplace(tessera::cuda::emulated_backend());
    on_device = Slab().values;
    tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), on_device.data(),
                                                  on_device.size() * sizeof(float));
  }
  const Run mixed = run(dir, "auto", "auto", world_rank() == 0 ? on_device.data() : nullptr);
  INFO(mixed.error);
  CHECK(all_ranks(mixed.status == TESSERA_OK));
  CHECK(all_ranks(mixed.device == "cpu"));
  if (world_rank() == 0) {
    REQUIRE(cpu.image);
    REQUIRE(mixed.image);
    CHECK(cpu.image->rgba == mixed.image->rgba);  // the CPU's bits: no tile rendered elsewhere
  }
}
