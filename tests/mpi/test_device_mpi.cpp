// tessera.device under MPI, on the host emulation of a GPU (core/src/cuda/gpu_emulation.h, in
// every build): one "GPU" per rank renders the CPU's image; ranks that disagree (a rank with
// no GPU) under device: cuda fail together, naming why, and the next call renders; under
// device: auto the ranks agree on one device kind, so the image does not depend on which rank
// renders a tile (a rank without a GPU sends every rank to the CPU); on the GPU each rank grabs
// large chunks of tiles and the gathered image is the one-rank GPU image bit for bit; mesh
// domains spread over the ranks render on every rank's GPU with device: cuda.
#include "../gpu/gpu_test_util.h"
#include "amr_patches.h"
#include "blob_slab.h"
#include "mesh_blocks.h"
#include "mpi_test_support.h"

#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"
#include "mpi/parallel_context_mpi.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera::insitu::Adapter;

namespace {

constexpr int kN = 16;

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
  std::uint64_t to_host = 0;            // stats.bytes_to_host
};

/// One call of an adapter opened on `device` over this rank's slab (`data`: the slab's values
/// or another copy of them), the field shared as `distribution` says.
Run run(const SharedTempDir& dir, const std::string& tag, const std::string& device, const void* data = nullptr,
        const std::string& distribution = "auto") {
  BlobSlab slab;
  if (data) slab.field.data = data;
  Adapter a;
  a.set_quiet(true);
  std::string text = config(dir.file(tag), device);
  text.replace(text.find("  threads: 1\n"), 13, "  threads: 1\n  distribution: " + distribution + "\n");
  const std::string cfg = dir.write(tag + ".yaml", text);
  REQUIRE(all_ranks(a.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
  Run r;
  r.status = a.execute(1, 0.0, slab.grid, {&slab.field, 1});
  r.error = a.last_error();
  if (!a.last_results().empty()) r.device = a.last_results()[0].device;
  if (!a.last_results().empty()) r.to_host = a.last_results()[0].stats.bytes_to_host;
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

/// A warped box of 4 blocks of cells (hexes and tets alternating), block b on rank b % ranks
/// (a rank may hold none): every block (each rank builds all), this rank's domains, and the
/// geometry's bytes (x, y, z, int32 connectivity) of the whole mesh and of this rank's.
struct SpreadMesh {
  std::deque<tessera_test::MeshBlock> blocks;
  std::vector<tessera_mesh_domain> mine;
  std::vector<const tessera_test::MeshBlock*> own;  ///< the blocks of `mine`
  std::uint64_t geometry = 0, my_geometry = 0;
  SpreadMesh() {
    const std::int64_t n[3] = {9, 8, 13};
    const std::int64_t cuts[5] = {0, 3, 6, 9, 12};
    for (int b = 0; b < 4; ++b) {
      tessera_test::MeshBlock& m = blocks.emplace_back(n, cuts[b], cuts[b + 1]);
      const bool tets = b % 2 == 1;
      const std::uint64_t bytes =
          3 * m.x.size() * sizeof(double) + (tets ? m.tets.size() : m.hexes.size()) * sizeof(std::int32_t);
      geometry += bytes;
      if (b % world_size() != world_rank()) continue;
      mine.push_back(m.domain(tets ? tessera_test::MeshBlock::Form::Tets : tessera_test::MeshBlock::Form::Hexes));
      own.push_back(&m);
      my_geometry += bytes;
    }
  }
  SpreadMesh(const SpreadMesh&) = delete;
  SpreadMesh& operator=(const SpreadMesh&) = delete;
  /// This rank's arrays declared device memory to the emulated GPU (which must be installed).
  void declare_mine_device() const {
    const auto declare = [](const auto& v) {
      tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), v.data(), v.size() * sizeof(v[0]));
    };
    for (const tessera_test::MeshBlock* m : own)
      declare(m->x), declare(m->y), declare(m->z), declare(m->vertex_values), declare(m->hexes), declare(m->tets);
  }
  /// Every vertex value times f.
  void rescale(double f) {
    for (tessera_test::MeshBlock& m : blocks)
      for (double& v : m.vertex_values) v *= f;
  }
  std::span<const tessera_mesh_domain> domains() const { return {mine.data(), mine.size()}; }
};

/// `a` opened on every rank with the mesh render's config (field f over [0, 1]) on `device`.
void open_mesh(Adapter& a, const SharedTempDir& dir, const std::string& tag, const std::string& device) {
  std::string cfg = config(dir.file(tag), device);
  cfg.replace(cfg.find("field: density"), 14, "field: f");
  cfg.replace(cfg.find("range: [0, 250]"), 15, "range: [0, 1]");
  a.set_quiet(true);
  REQUIRE(all_ranks(a.open(dir.write(tag + ".yaml", cfg), MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
}

/// One call over the SpreadMesh on `device`. `rank0_on_device`: rank 0's arrays are declared
/// device memory to the emulated GPU (which must be installed).
Run run_mesh(const SharedTempDir& dir, const std::string& tag, const std::string& device,
             bool rank0_on_device = false) {
  const SpreadMesh mesh;
  if (rank0_on_device && world_rank() == 0) mesh.declare_mine_device();
  Adapter a;
  open_mesh(a, dir, tag, device);
  Run r;
  r.status = a.execute_mesh_domains(1, 0.0, mesh.domains());
  r.error = a.last_error();
  if (!a.last_results().empty()) r.device = a.last_results()[0].device;
  if (const tessera::Image* im = a.last_image("view")) r.image = *im;
  return r;
}

}  // namespace

TEST_CASE("device: cuda renders mesh domains spread over the ranks: the CPU's image", "[mpi][gpu][mesh]") {
  SharedTempDir dir("tessera_device_");
  const Run cpu = run_mesh(dir, "mesh_cpu", "cpu");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const Run dev = run_mesh(dir, "mesh_cuda", "cuda");
  const Run automatic = run_mesh(dir, "mesh_auto", "auto");  // host arrays: the CPU
  INFO(dev.error);
  CHECK(all_ranks(cpu.status == TESSERA_OK));
  CHECK(all_ranks(dev.status == TESSERA_OK));
  CHECK(all_ranks(dev.device == "cuda:0"));
  CHECK(all_ranks(automatic.device == "cpu"));
  if (world_rank() == 0) {
    REQUIRE(cpu.image);
    REQUIRE(dev.image);
    REQUIRE(automatic.image);
    CHECK(max_difference(*cpu.image, *dev.image) < 1e-5);
    CHECK(cpu.image->rgba == automatic.image->rgba);
  }
}

TEST_CASE("device: auto with mesh arrays in device memory on rank 0", "[mpi][gpu][mesh]") {
  // Rank 0's arrays are copied to the host; alone it renders on its GPU, reading them there;
  // with other ranks, whose arrays are host memory, every rank renders on the CPU
  SharedTempDir dir("tessera_device_");
  const Run cpu = run_mesh(dir, "mesh_cpu", "cpu");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const Run dev = run_mesh(dir, "mesh_dev", "auto", true);
  INFO(dev.error);
  CHECK(all_ranks(dev.status == TESSERA_OK));
  CHECK(all_ranks(dev.device == (world_size() == 1 ? "cuda:0" : "cpu")));
  if (world_rank() == 0) {
    REQUIRE(cpu.image);
    REQUIRE(dev.image);
    if (world_size() == 1) CHECK(max_difference(*cpu.image, *dev.image) < 1e-5);
    else CHECK(cpu.image->rgba == dev.image->rgba);  // the CPU's bits: no tile rendered elsewhere
  }
}

TEST_CASE("device: cuda over an unchanged mesh on the ranks' GPUs copies only its values again", "[mpi][gpu][mesh]") {
  // Calls 2 and 3 pass new values over the same geometry (found the same by its hash, then
  // promised): every rank's GPU keeps the whole mesh's geometry and lookup tables from call 1
  // (on several ranks the geometry is the kept bytes of call 1's full exchange, and only the
  // values move), so those calls copy at least the whole geometry's bytes fewer, and the image
  // is a fresh adapter's bit for bit
  SharedTempDir dir("tessera_device_");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  SpreadMesh mesh;
  const std::uint64_t geometry = mesh.geometry;  // of the whole mesh
  const auto open = [&](Adapter& a, const std::string& tag) { open_mesh(a, dir, tag, "cuda"); };
  Adapter a;
  open(a, "kept");
  REQUIRE(all_ranks(a.execute_mesh_domains(1, 0.0, mesh.domains()) == TESSERA_OK));
  const tessera::insitu::RenderResult first = a.last_results().at(0);
  mesh.rescale(0.8);
  REQUIRE(all_ranks(a.execute_mesh_domains(2, 0.1, mesh.domains()) == TESSERA_OK));
  const tessera::insitu::RenderResult found = a.last_results().at(0);
  std::optional<tessera::Image> image;
  if (const tessera::Image* im = a.last_image("view")) image = *im;
  REQUIRE(all_ranks(a.mesh_unchanged() == TESSERA_OK));
  REQUIRE(all_ranks(a.execute_mesh_domains(3, 0.2, mesh.domains()) == TESSERA_OK));
  const tessera::insitu::RenderResult promised = a.last_results().at(0);
  CHECK(all_ranks(first.device == "cuda:0"));
  CHECK(all_ranks(!first.mesh_layout_reused && found.mesh_layout_reused && promised.mesh_layout_reused));
  CHECK(all_ranks(found.mesh_values_only == (world_size() > 1)));
  INFO("bytes to the device: " << first.stats.bytes_to_device << ", " << found.stats.bytes_to_device << ", "
                               << promised.stats.bytes_to_device << "; the geometry " << geometry);
  // (on several ranks each rank's share of the tiles, and so of the film's bytes, varies)
  CHECK(all_ranks(found.stats.bytes_to_device + geometry < first.stats.bytes_to_device));
  CHECK(all_ranks(promised.stats.bytes_to_device + geometry < first.stats.bytes_to_device));
  if (world_size() == 1) CHECK(promised.stats.bytes_to_device == found.stats.bytes_to_device);
  // Call 2's values (call 3's too), a fresh adapter (everything copied): the same bits
  Adapter fresh;
  open(fresh, "fresh");
  REQUIRE(all_ranks(fresh.execute_mesh_domains(2, 0.1, mesh.domains()) == TESSERA_OK));
  CHECK(all_ranks(fresh.last_results().at(0).stats.bytes_to_device > found.stats.bytes_to_device + geometry));
  if (world_size() == 1) CHECK(fresh.last_results().at(0).stats.bytes_to_device == first.stats.bytes_to_device);
  if (world_rank() == 0) {
    REQUIRE(image);
    REQUIRE(fresh.last_image("view"));
    CHECK(fresh.last_image("view")->rgba == image->rgba);
  }
}

TEST_CASE("ranks whose mesh is device memory and unchanged stage only its values to the host", "[mpi][gpu][mesh]") {
  // Every rank's arrays in (emulated) device memory, rendered on the CPU so that bytes_to_host
  // is the staging alone. Call 1 stages everything and exchanges the geometry; calls 2
  // (found the same by its hash on the device) and 3 (promised) stage only the values, the
  // geometry read from call 1's exchange. At call 4 rank 0's mesh moves: no rank holds the
  // exchange's geometry any more, so every rank stages its geometry too. Each image is a
  // fresh adapter's bit for bit (everything staged)
  SharedTempDir dir("tessera_device_");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  SpreadMesh mesh;
  mesh.declare_mine_device();
  const std::uint64_t geometry = mesh.my_geometry;  // this rank's
  const auto open = [&](Adapter& a, const std::string& tag) { open_mesh(a, dir, tag, "cpu"); };
  Adapter a;
  open(a, "kept");
  // Call s of `a`, and the same state through a fresh adapter: the results, and whether rank
  // 0's images are the same bits
  const auto call = [&](int s) {
    REQUIRE(all_ranks(a.execute_mesh_domains(s, 0.1 * s, mesh.domains()) == TESSERA_OK));
    Adapter fresh;
    open(fresh, "fresh" + std::to_string(s));
    REQUIRE(all_ranks(fresh.execute_mesh_domains(s, 0.1 * s, mesh.domains()) == TESSERA_OK));
    bool same = true;
    if (world_rank() == 0) {
      REQUIRE(a.last_image("view"));
      REQUIRE(fresh.last_image("view"));
      same = a.last_image("view")->rgba == fresh.last_image("view")->rgba;
    }
    CHECK(all_ranks(fresh.last_results().at(0).stats.bytes_to_host ==
                    a.last_results().at(0).stats.bytes_to_host +
                        (a.last_results().at(0).mesh_layout_reused && world_size() > 1 ? geometry : 0)));
    CHECK(same);
    return a.last_results().at(0);
  };
  const tessera::insitu::RenderResult first = call(1);
  mesh.rescale(0.8);
  const tessera::insitu::RenderResult found = call(2);
  mesh.rescale(0.9);
  REQUIRE(all_ranks(a.mesh_unchanged() == TESSERA_OK));
  const tessera::insitu::RenderResult promised = call(3);
  CHECK(all_ranks(first.device == "cpu"));
  CHECK(all_ranks(!first.mesh_layout_reused && found.mesh_layout_reused && promised.mesh_layout_reused));
  CHECK(all_ranks(found.mesh_values_only == (world_size() > 1) && promised.mesh_values_only == (world_size() > 1)));
  const std::uint64_t saved = world_size() > 1 ? geometry : 0;  // one rank: staged whole, always
  CHECK(all_ranks(found.stats.bytes_to_host + saved == first.stats.bytes_to_host));
  CHECK(all_ranks(promised.stats.bytes_to_host == found.stats.bytes_to_host));
  // Rank 0's first block moves (no promise there; the other ranks promise theirs unchanged):
  // no rank holds the exchange's geometry any more, so every rank stages its geometry too
  mesh.blocks.front().x[5] += 1e-3;
  mesh.rescale(1.1);
  if (world_rank() != 0) REQUIRE(a.mesh_unchanged() == TESSERA_OK);
  const tessera::insitu::RenderResult moved = call(4);
  CHECK(all_ranks(!moved.mesh_values_only && !moved.mesh_layout_reused));
  CHECK(all_ranks(moved.stats.bytes_to_host == first.stats.bytes_to_host));
  // Nothing promised, nothing moved: every rank finds its geometry by its hash (the promising
  // ranks' too, hashed when they staged it at call 4), so only the values move again
  mesh.rescale(0.9);
  const tessera::insitu::RenderResult again = call(5);
  CHECK(all_ranks(again.mesh_layout_reused && again.mesh_values_only == (world_size() > 1)));
  CHECK(all_ranks(again.stats.bytes_to_host + saved == first.stats.bytes_to_host));
}

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

TEST_CASE("refinement levels over the ranks: on every rank's GPU when replicated, never distributed",
          "[mpi][gpu][amr]") {
  // A 3-level hierarchy of cell data, its patches dealt round robin over the ranks. With their
  // kernel (-DTESSERA_CUDA_AMR, the default of CUDA builds): replicated, device cuda renders
  // the CPU's image on every rank's GPU; on several ranks without `distribution: replicated`
  // (distributed mode may be chosen, and has no GPU kernel for them) device cuda fails on every
  // rank by name. Without it, device cuda refuses refinement levels by name.
  SharedTempDir dir("tessera_device_");
  const tessera_test::Hierarchy h = tessera_test::hierarchy(3, TESSERA_CELL);
  const tessera_test::HeldPatches held(h.spec, h.many, tessera_test::blobs, 2);
  const tessera_mesh mesh = h.spec.mesh();
  const auto call = [&](const std::string& tag, const std::string& device, const std::string& distribution) {
    Adapter a;
    a.set_quiet(true);
    std::string text = config(dir.file(tag), device);
    text.replace(text.find("  threads: 1\n"), 13, "  threads: 1\n  distribution: " + distribution + "\n");
    REQUIRE(all_ranks(a.open(dir.write(tag + ".yaml", text), MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
    const std::vector<tessera_domain> mine = held.of_rank(
        world_rank(), [](std::size_t p) { return static_cast<int>(p % static_cast<std::size_t>(world_size())); });
    Run r;
    r.status = a.execute_domains(1, 0.0, mesh, mine);
    r.error = a.last_error();
    if (!a.last_results().empty()) r.device = a.last_results()[0].device;
    if (const tessera::Image* im = a.last_image("view")) r.image = *im;
    return r;
  };
  const Run cpu = call("amr_cpu", "cpu", "replicated");
  REQUIRE(all_ranks(cpu.status == TESSERA_OK));
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const Run replicated = call("amr_cuda", "cuda", "replicated");
  INFO(replicated.error);
#if defined(TESSERA_CUDA_AMR)
  CHECK(all_ranks(replicated.status == TESSERA_OK));
  CHECK(all_ranks(replicated.device == "cuda:0"));
  if (world_rank() == 0) {
    REQUIRE(cpu.image);
    REQUIRE(replicated.image);
    CHECK(max_difference(*cpu.image, *replicated.image) < 1e-5);
  }
  if (world_size() > 1) {
    const Run maybe_distributed = call("amr_cuda_auto", "cuda", "auto");
    INFO(maybe_distributed.error);
    CHECK(all_ranks(maybe_distributed.status == TESSERA_ERROR_RENDER));
    CHECK(all_ranks(maybe_distributed.error.find("refinement levels on several ranks") != std::string::npos));
  }
#else
  CHECK(all_ranks(replicated.status == TESSERA_ERROR_RENDER));
  CHECK(all_ranks(replicated.error.find("refinement levels") != std::string::npos));
#endif
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
    on_device = BlobSlab().values;
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

TEST_CASE("on GPUs the ranks grab large chunks and gather the one-rank GPU image bit for bit", "[mpi][gpu]") {
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const std::vector<double> field = gpu_test::heat_field<double>(kN);
  tessera::SceneDesc s = gpu_test::heat_scene(kN, 31);
  s.options.device = tessera::Device::Cuda;
  s.options.tile = 8;  // 48x48: 36 tiles
  const tessera::PreparedScene ps =
      tessera::prepare(tessera::FieldView::contiguous(field.data(), tessera::DType::Float64, kN, kN, kN), s);
  const int ntiles = static_cast<int>(ps.tiles().size());
  tessera::Film one(48, 48);
  tessera::RenderStats one_stats;
  tessera::render_tiles(ps, gpu_test::all_tiles(ps), one, one_stats);  // this rank alone, on its GPU
  tessera::insitu::MpiParallelContext ctx(MPI_COMM_WORLD, 0);
  tessera::Film film(48, 48);
  tessera::RenderStats stats;
  ctx.render(ps, film, stats);
  // (one rank renders every tile in one call)
  const int n = world_size(), chunk = n == 1 ? ntiles : (ntiles + 2 * n - 1) / (2 * n);
  int grabs = ctx.report().grabs, all_grabs = 0;
  MPI_Allreduce(&grabs, &all_grabs, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  CHECK(all_ranks(ctx.report().chunk == chunk));
  CHECK(all_ranks(all_grabs == (ntiles + chunk - 1) / chunk));  // about two per rank
  if (world_rank() == 0) {
    CHECK(gpu_test::same_bits(film, one));
    CHECK(stats.real_collisions == one_stats.real_collisions);
  }
}

TEST_CASE("device: cuda in distributed mode renders the replicated GPU image bit for bit", "[mpi][gpu][paged]") {
  // Every rank holds its slab only; the other ranks' bricks come over MPI to the host cache
  // and from there to each rank's GPU as its launches miss them (replayed launches)
  SharedTempDir dir("tessera_device_");
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend());
  const Run replicated = run(dir, "replicated", "cuda", nullptr, "replicated");
  const Run distributed = run(dir, "distributed", "cuda", nullptr, "distributed");
  INFO(distributed.error);
  CHECK(all_ranks(replicated.status == TESSERA_OK));
  CHECK(all_ranks(distributed.status == TESSERA_OK));
  CHECK(all_ranks(distributed.device == "cuda:0"));
  if (world_rank() == 0) {
    REQUIRE(replicated.image);
    REQUIRE(distributed.image);
    CHECK(replicated.image->rgba == distributed.image->rgba);
  }
  // device: auto with the slabs in (emulated) device memory: the GPU, the same bits (each
  // rank's slab read where it is; the bytes this saves depend on which tiles a rank grabs,
  // so test_gpu_paged.cpp counts them)
  std::vector<float> on_device = BlobSlab().values;
  tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), on_device.data(),
                                                on_device.size() * sizeof(float));
  const Run from_device = run(dir, "auto", "auto", on_device.data(), "distributed");
  INFO(from_device.error);
  CHECK(all_ranks(from_device.status == TESSERA_OK));
  CHECK(all_ranks(from_device.device == "cuda:0"));
  if (world_rank() == 0) {
    REQUIRE(from_device.image);
    CHECK(replicated.image->rgba == from_device.image->rgba);
  }
  // Replicated with the slabs in device memory on several ranks: staged once the plan is
  // known (the whole slab, counted), the same bits; on one rank read in place
  const Run staged = run(dir, "staged", "cuda", on_device.data(), "replicated");
  INFO(staged.error);
  CHECK(all_ranks(staged.status == TESSERA_OK));
  if (world_rank() == 0) {
    // rank 0's count: every rank's render copies (the same as the host slabs' render) and its
    // own staging
    INFO("to host " << staged.to_host << ", from host slabs " << replicated.to_host);
    CHECK(staged.to_host - replicated.to_host == (world_size() > 1 ? on_device.size() * sizeof(float) : 0));
    REQUIRE(staged.image);
    CHECK(replicated.image->rgba == staged.image->rgba);
  }
  tessera::cuda::emulated_forget_device_memory(*tessera::cuda::gpu_emulation(), on_device.data());
}

TEST_CASE("device: cuda in distributed mode: a device slab that cannot be copied fails every rank, none hangs",
          "[mpi][gpu][paged]") {
  // The last rank's slab stays in (emulated) device memory; its copies out fail (as from an
  // array freed under the render) first in the summary's reduction, then in the bricks the
  // other ranks and its own cache ask for: every rank fails the call (the failing rank
  // names the copy), no rank waits for a reply or a collective that never comes, and the
  // next call, with the copies working, renders the replicated image bit for bit
  if (world_size() < 2) return;
  SharedTempDir dir("tessera_device_");
  std::vector<float> on_device = BlobSlab().values;
  const void* slab = on_device.data();
  const std::size_t bytes = on_device.size() * sizeof(float);
  const bool faulty_rank = world_rank() == world_size() - 1;
  std::string failing;  // the copy that fails: "" none
  tessera::cuda::EmulatedDevice d;
  d.copy_out_fault = [&](const void* src, const std::string& what) {
    const auto* p = static_cast<const unsigned char*>(src);
    const auto* b = static_cast<const unsigned char*>(slab);
    return faulty_rank && what == failing && p >= b && p < b + bytes;
  };
  const tessera::cuda::ScopedGpuEmulation gpu(tessera::cuda::emulated_backend(d));
  tessera::cuda::emulated_declare_device_memory(*tessera::cuda::gpu_emulation(), slab, bytes);
  const Run replicated = run(dir, "replicated", "cuda", nullptr, "replicated");
  for (const char* what : {"cuda_field_summary_accumulate", "cuda_copy_box_to_host"}) {
    failing = what;
    const Run broken = run(dir, std::string("broken_") + what, "cuda", slab, "distributed");
    INFO(what << ": " << broken.error);
    CHECK(all_ranks(broken.status != TESSERA_OK));
    if (faulty_rank) CHECK(broken.error.find(what) != std::string::npos);
  }
  failing.clear();
  const Run fixed = run(dir, "fixed", "cuda", slab, "distributed");
  INFO(fixed.error);
  CHECK(all_ranks(fixed.status == TESSERA_OK));
  if (world_rank() == 0) {
    REQUIRE(replicated.image);
    REQUIRE(fixed.image);
    CHECK(replicated.image->rgba == fixed.image->rgba);
  }
  tessera::cuda::emulated_forget_device_memory(*tessera::cuda::gpu_emulation(), slab);
}
