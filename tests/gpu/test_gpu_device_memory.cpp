// Device memory and the backend's guards (docs/gpu.md): where a pointer lives, a field read in
// place from device memory (any strides) with no field bytes copied, the device field summary
// against the host's bit for bit, the prepared scene's device copies kept between calls, the
// memory limit and the device's free memory checked before allocating, and a launch failure
// that disables the GPU for the process (in a child process: the context is lost after it).
#include "gpu_test_util.h"

#include <tessera/cuda_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/field_summary.h>
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include <cuda_runtime_api.h>
#include <sys/mman.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace gpu_test;
using tessera::DType;
using tessera::MemoryKind;

namespace {

/// A device copy of n bytes, freed with the object.
struct DeviceArray {
  void* p = nullptr;
  DeviceArray(const void* host, std::size_t n) {
    REQUIRE(cudaMalloc(&p, n) == cudaSuccess);
    REQUIRE(cudaMemcpy(p, host, n, cudaMemcpyHostToDevice) == cudaSuccess);
  }
  ~DeviceArray() { cudaFree(p); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
};

/// The same view over another base: data moved by (base - host base).
FieldView rebased(const FieldView& v, const void* host_base, const void* base) {
  FieldView r = v;
  r.data = static_cast<const unsigned char*>(base) +
           (static_cast<const unsigned char*>(v.data) - static_cast<const unsigned char*>(host_base));
  return r;
}

bool same_summary(const tessera::FieldSummary& a, const tessera::FieldSummary& b) {
  if (a.cell_count() != b.cell_count() || a.nan_vertices() != b.nan_vertices() ||
      a.element_count() != b.element_count() || a.has_finite() != b.has_finite() || a.edge() != b.edge())
    return false;
  const double amin = a.value_min(), bmin = b.value_min(), amax = a.value_max(), bmax = b.value_max();
  if (std::memcmp(&amin, &bmin, 8) != 0 || std::memcmp(&amax, &bmax, 8) != 0) return false;
  for (std::int64_t c = 0; c < a.cell_count(); ++c) {
    const tessera::CellRange &x = a.ranges()[static_cast<std::size_t>(c)], &y = b.ranges()[static_cast<std::size_t>(c)];
    if (std::memcmp(&x.lo, &y.lo, 8) != 0 || std::memcmp(&x.hi, &y.hi, 8) != 0 || x.nan != y.nan ||
        x.pos_inf != y.pos_inf || x.neg_inf != y.neg_inf)
      return false;
  }
  return true;
}

/// Values of type T for the summary test: a ramp with, for float types, NaN, +-Inf and -0.0.
template <class T>
std::vector<T> summary_values(std::size_t n) {
  std::vector<T> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::sin(0.37 * static_cast<double>(i)) * 100.0 + 100.0;
    v[i] = static_cast<T>(std::is_signed_v<T> ? x - 150.0 : x);
    if constexpr (std::is_floating_point_v<T>) {
      if (i % 53 == 7) v[i] = std::numeric_limits<T>::quiet_NaN();
      if (i % 71 == 3) v[i] = std::numeric_limits<T>::infinity();
      if (i % 89 == 5) v[i] = -std::numeric_limits<T>::infinity();
      if (i % 13 == 2) v[i] = static_cast<T>(-0.0);
    }
  }
  return v;
}

/// cuda_field_summary of device copies of several views of one padded array (contiguous
/// interior, a ghost-layer view, negative strides along y and z) against FieldSummary::build
/// of the same views of the host array, for two edges.
template <class T>
void check_summary(DType dtype) {
  const std::int64_t full[3] = {15, 13, 11};  // the interior 13 x 11 x 9 plus one ghost layer
  const std::size_t n = static_cast<std::size_t>(full[0] * full[1] * full[2]);
  const std::vector<T> host = summary_values<T>(n);
  DeviceArray dev(host.data(), n * sizeof(T));
  const std::int64_t e = sizeof(T), s[3] = {e, e * full[0], e * full[0] * full[1]};
  std::vector<FieldView> views;
  views.push_back(FieldView::contiguous(host.data(), dtype, full[0], full[1], full[2]));
  FieldView ghost;  // the interior: one ghost layer on every side
  ghost.data = host.data() + (1 + full[0] * (1 + full[1]));
  ghost.dtype = dtype;
  for (int a = 0; a < 3; ++a) {
    ghost.dims[a] = full[a] - 2;
    ghost.byte_strides[a] = s[a];
  }
  views.push_back(ghost);
  FieldView flipped = ghost;  // y and z reversed: data at the last interior row and layer
  flipped.data =
      static_cast<const unsigned char*>(ghost.data) + (ghost.dims[1] - 1) * s[1] + (ghost.dims[2] - 1) * s[2];
  flipped.byte_strides[1] = -s[1];
  flipped.byte_strides[2] = -s[2];
  views.push_back(flipped);
  for (const FieldView& hv : views)
    for (const int edge : {4, 16}) {
      const FieldView dv = rebased(hv, host.data(), dev.p);
      const auto want = tessera::FieldSummary::build(hv, edge);
      const auto got = tessera::cuda_field_summary(dv, edge);
      INFO(tessera::dtype_name(dtype) << " view with strides " << hv.byte_strides[0] << "," << hv.byte_strides[1] << ","
                                      << hv.byte_strides[2] << ", edge " << edge);
      CHECK(same_summary(*want, *got));
      CHECK(got->matches(dv, edge));
      // A host pointer: summarised on the host
      CHECK(same_summary(*want, *tessera::cuda_field_summary(hv, edge)));
    }
}

/// The scene's GPU render of a device copy of `host` (n^3 floats) viewed as `view_of(base)`.
tessera::Film render_device_view(const std::vector<float>& host, const std::function<FieldView(const void*)>& view_of,
                                 const tessera::SceneDesc& s, tessera::CudaTransfer* tr) {
  DeviceArray dev(host.data(), host.size() * sizeof(float));
  const FieldView v = view_of(dev.p);
  REQUIRE(tessera::cuda_memory_kind(v.data) == MemoryKind::Device);
  const auto summary = tessera::cuda_field_summary(v, tessera::majorant_edge(v, s.integrator));
  const tessera::PreparedScene ps = tessera::prepare(v, s, summary);
  REQUIRE(ps.summary_reused());  // prepare read no value of the device field
  return render_gpu(ps, {}, tr);
}

}  // namespace

TEST_CASE("GPU: where a pointer lives", "[gpu][memory]") {
  std::vector<float> host(64);
  float on_stack = 0.0f;
  void *dev = nullptr, *managed = nullptr, *pinned = nullptr;
  REQUIRE(cudaMalloc(&dev, 256) == cudaSuccess);
  REQUIRE(cudaMallocManaged(&managed, 256) == cudaSuccess);
  REQUIRE(cudaMallocHost(&pinned, 256) == cudaSuccess);
  CHECK(tessera::cuda_memory_kind(host.data()) == MemoryKind::Host);
  CHECK(tessera::cuda_memory_kind(&on_stack) == MemoryKind::Host);
  CHECK(tessera::cuda_memory_kind(nullptr) == MemoryKind::Host);
  CHECK(tessera::cuda_memory_kind(pinned) == MemoryKind::Host);
  CHECK(tessera::cuda_memory_kind(dev) == MemoryKind::Device);
  CHECK(tessera::cuda_memory_kind(static_cast<char*>(dev) + 100) == MemoryKind::Device);
  CHECK(tessera::cuda_memory_kind(managed) == MemoryKind::Managed);
  CHECK(cudaGetLastError() == cudaSuccess);  // nothing left behind
  CHECK_FALSE(tessera::cuda_disabled());
  cudaFree(dev);
  cudaFree(managed);
  cudaFreeHost(pinned);
}

TEST_CASE("GPU: the device field summary equals the host's bit for bit", "[gpu][memory][summary]") {
  check_summary<std::uint8_t>(DType::UInt8);
  check_summary<std::int16_t>(DType::Int16);
  check_summary<std::uint16_t>(DType::UInt16);
  check_summary<float>(DType::Float32);
  check_summary<double>(DType::Float64);
}

TEST_CASE("GPU: a device field is read in place, with the same bits as its host copy", "[gpu][memory]") {
  constexpr int n = 32;
  const std::vector<float> field = heat_field<float>(n);
  const tessera::SceneDesc s = heat_scene(n, 21);
  tessera::CudaTransfer host_tr, dev_tr, ghost_tr, flip_tr;
  const tessera::Film from_host =
      render_gpu(tessera::prepare(FieldView::contiguous(field.data(), DType::Float32, n, n, n), s), {}, &host_tr);
  const tessera::Film in_place = render_device_view(
      field, [&](const void* p) { return FieldView::contiguous(p, DType::Float32, n, n, n); }, s, &dev_tr);
  INFO("host field: " << host_tr.bytes_to_device << " bytes to the device; device field: " << dev_tr.bytes_to_device);
  CHECK_FALSE(host_tr.field_in_place);
  CHECK(dev_tr.field_in_place);
  CHECK(host_tr.bytes_to_device - dev_tr.bytes_to_device == field.size() * sizeof(float));
  CHECK(same_bits(from_host, in_place));

  // The same values behind a ghost layer, and stored reversed along z (negative stride)
  constexpr int g = n + 2;
  std::vector<float> padded(static_cast<std::size_t>(g) * g * g, -1.0e30f), reversed(field.size());
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const float v = field[(static_cast<std::size_t>(k) * n + j) * n + i];
        padded[(static_cast<std::size_t>(k + 1) * g + j + 1) * g + i + 1] = v;
        reversed[(static_cast<std::size_t>(n - 1 - k) * n + j) * n + i] = v;
      }
  const tessera::Film ghosts = render_device_view(
      padded,
      [&](const void* p) {
        FieldView v = FieldView::contiguous(static_cast<const float*>(p) + (1 + g * (1 + g)), DType::Float32, n, n, n);
        v.byte_strides[1] = 4 * g;
        v.byte_strides[2] = 4 * g * g;
        return v;
      },
      s, &ghost_tr);
  const tessera::Film flipped = render_device_view(
      reversed,
      [&](const void* p) {
        FieldView v = FieldView::contiguous(static_cast<const float*>(p) + (n - 1) * n * n, DType::Float32, n, n, n);
        v.byte_strides[2] = -4 * n * n;
        return v;
      },
      s, &flip_tr);
  CHECK(ghost_tr.field_in_place);
  CHECK(flip_tr.field_in_place);
  CHECK(ghost_tr.bytes_to_device == dev_tr.bytes_to_device);
  CHECK(same_bits(from_host, ghosts));
  CHECK(same_bits(from_host, flipped));

  // The host copy of a strided host field is exactly its span
  tessera::CudaTransfer strided_tr;
  FieldView hv = FieldView::contiguous(padded.data() + (1 + g * (1 + g)), DType::Float32, n, n, n);
  hv.byte_strides[1] = 4 * g;
  hv.byte_strides[2] = 4 * g * g;
  const tessera::Film strided = render_gpu(tessera::prepare(hv, s), {}, &strided_tr);
  const std::uint64_t span = 4 * ((n - 1) + (n - 1) * g + (n - 1) * g * g + 1);
  CHECK(strided_tr.bytes_to_device - dev_tr.bytes_to_device == span);
  CHECK(same_bits(from_host, strided));
}

TEST_CASE("GPU: the scene's device copies are kept between calls", "[gpu][memory][cache]") {
  constexpr int n = 32;
  const std::vector<float> field = heat_field<float>(n);
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), DType::Float32, n, n, n), heat_scene(n, 3));
  const tessera::Film whole =
      render_gpu(tessera::prepare(FieldView::contiguous(field.data(), DType::Float32, n, n, n), heat_scene(n, 3)));
  // The MPI scheduler's pattern: a few tiles per call
  const std::vector<int> tiles = all_tiles(ps);
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  std::vector<tessera::CudaTransfer> tr;
  for (std::size_t t0 = 0; t0 < tiles.size(); t0 += 2) {
    const std::vector<int> some(tiles.begin() + static_cast<std::ptrdiff_t>(t0),
                                tiles.begin() + static_cast<std::ptrdiff_t>(std::min(t0 + 2, tiles.size())));
    tessera::CudaTransfer t;
    tessera::render_tiles_cuda(ps, some, film, st, {}, &t);
    tr.push_back(t);
  }
  REQUIRE(tr.size() >= 2);
  CHECK_FALSE(tr[0].scene_reused);
  CHECK(tr[0].bytes_to_device > field.size() * sizeof(float));
  for (std::size_t i = 1; i < tr.size(); ++i) {
    INFO("call " << i << ": " << tr[i].bytes_to_device << " bytes to the device, " << tr[i].device_bytes << " held");
    CHECK(tr[i].scene_reused);
    // the pixel list (12 bytes a pixel), the pixel sums and the counters only
    std::uint64_t pixels = 0;
    for (std::size_t t = 2 * i; t < std::min(2 * i + 2, tiles.size()); ++t) {
      const tessera::Tile& tile = ps.tiles()[static_cast<std::size_t>(tiles[t])];
      pixels += static_cast<std::uint64_t>((tile.x1 - tile.x0) * (tile.y1 - tile.y0));
    }
    CHECK(tr[i].bytes_to_device == pixels * (12 + sizeof(tessera::PixelSums)) + 8 * sizeof(std::uint64_t));
    CHECK(tr[i].device_bytes > field.size() * sizeof(float));  // the kept copies count
  }
  CHECK(same_bits(whole, film));
}

TEST_CASE("GPU: the memory limit and the device's free memory are checked before allocating", "[gpu][memory]") {
  constexpr int n = 16;
  const std::vector<float> field = heat_field<float>(n);
  const tessera::PreparedScene ps =
      tessera::prepare(FieldView::contiguous(field.data(), DType::Float32, n, n, n), heat_scene(n, 3));
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  tessera::CudaLaunch tight;
  tight.memory_limit_bytes = 4096;
  CHECK_THROWS_WITH(tessera::render_tiles_cuda(ps, all_tiles(ps), film, st, tight),
                    Catch::Contains("memory limit of 4096 bytes") && Catch::Contains("needs"));
  tessera::CudaTransfer tr;
  tessera::render_tiles_cuda(ps, all_tiles(ps), film, st, {}, &tr);  // without the limit it renders
  CHECK(tr.device_bytes > 4096);

  // A host field whose span (a 2x2x2 view with a 256 GiB stride over a reserved, never
  // touched mapping) is larger than any device's memory: refused, naming both sizes
  const std::size_t stride = std::size_t{1} << 38, map_bytes = stride + 4096;
  void* big = mmap(nullptr, map_bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  REQUIRE(big != MAP_FAILED);
  FieldView huge = FieldView::contiguous(big, DType::Float32, 2, 2, 2);
  huge.byte_strides[2] = static_cast<std::int64_t>(stride);
  tessera::SceneDesc s = heat_scene(2, 4);
  s.tf.lo = -1.0;
  s.tf.hi = 1.0;
  std::size_t free_before = 0, total = 0, free_after = 0;
  REQUIRE(cudaMemGetInfo(&free_before, &total) == cudaSuccess);
  {
    const tessera::PreparedScene big_scene = tessera::prepare(huge, s);
    tessera::Film f(48, 48);
    CHECK_THROWS_WITH(tessera::render_tiles_cuda(big_scene, all_tiles(big_scene), f, st),
                      Catch::Contains("needs 2748") && Catch::Contains("free of"));
  }
  REQUIRE(cudaMemGetInfo(&free_after, &total) == cudaSuccess);
  CHECK(free_after == free_before);  // nothing was allocated (or kept)
  munmap(big, map_bytes);
}

TEST_CASE("GPU: a launch failure disables the GPU for the process (child process)", "[gpu][sticky]") {
  // The child runs the hidden test below: after its illegal address the CUDA context of that
  // process is lost, so it must not be this one
  char exe[4096] = {};
  REQUIRE(readlink("/proc/self/exe", exe, sizeof exe - 1) > 0);
  const std::string log = "/tmp/tessera_gpu_sticky_" + std::to_string(getpid()) + ".log";
  const std::string cmd = std::string("'") + exe + "' '[.sticky_child]' > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(log.c_str());
  INFO("child output:\n" << text.str());
  CHECK(rc == 0);
}

TEST_CASE("GPU child: an illegal address in the kernel", "[.sticky_child]") {
  // A device field whose z stride reaches a terabyte past its allocation; a summary made up
  // for its layout, so that prepare reads nothing; the device loads fault (the float32
  // pixel kernel reads it in place; with -DTESSERA_CUDA_FLOAT32=OFF the widening kernel first)
#if defined(TESSERA_CUDA_FLOAT32)
  const std::string faulting = "pixel_samples<float32>";
#else
  const std::string faulting = "widen (float32 field to float64)";
#endif
  void* dev = nullptr;
  REQUIRE(cudaMalloc(&dev, 1 << 20) == cudaSuccess);
  FieldView v = FieldView::contiguous(dev, DType::Float32, 16, 16, 16);
  v.byte_strides[2] = std::int64_t{1} << 36;
  tessera::SceneDesc s = heat_scene(16, 1);
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  const int edge = tessera::majorant_edge(v, s.integrator);
  tessera::FieldSummary::Parts parts;
  for (int a = 0; a < 3; ++a) parts.cells[a] = (15 + edge - 1) / edge;
  const auto cells = static_cast<std::size_t>(parts.cells[0] * parts.cells[1] * parts.cells[2]);
  parts.lo.assign(cells, 0.0);
  parts.hi.assign(cells, 1.0);
  parts.flags.assign(cells, 0);
  parts.vmin = 0.0;
  parts.vmax = 1.0;
  const auto summary = tessera::FieldSummary::from_parts(std::move(parts), tessera::FieldLayout::of(v), edge);
  const tessera::PreparedScene ps = tessera::prepare(v, s, summary);
  REQUIRE(ps.summary_reused());
  tessera::Film film(48, 48);
  tessera::RenderStats st;
  CHECK_THROWS_WITH(tessera::render_tiles_cuda(ps, all_tiles(ps), film, st),
                    Catch::Contains(faulting) && Catch::Contains("cudaError"));
  std::string why;
  CHECK(tessera::cuda_disabled(&why));
  INFO("disabled by: " << why);
  CHECK(why.find(faulting) != std::string::npos);
  // Every later call says so at once
  CHECK_THROWS_WITH(tessera::render_tiles_cuda(ps, all_tiles(ps), film, st),
                    Catch::Contains("disabled for the process") && Catch::Contains(faulting));
  CHECK_THROWS_WITH(tessera::cuda_memory_kind(dev), Catch::Contains("disabled for the process"));
  CHECK_THROWS_WITH(tessera::cuda_field_summary(v, edge), Catch::Contains("disabled for the process"));
  CHECK(tessera::cuda_device_count() == 0);
}

TEST_CASE("GPU: a device block's summary at an offset and a box copied from it are the host's bit for bit",
          "[gpu][memory][summary][paged]") {
  // A 13x11x9 float64 block at offset (5, 3, 7) of a 40x30x20 field, its y axis stored
  // backwards, with NaN, +-Inf and -0.0 among its values: cuda_field_summary_accumulate folds
  // it into the global parts (over the block's window of macrocells only) as
  // FieldSummary::accumulate does, for edges 1, 4 and 8; cuda_copy_box_to_host packs a
  // sub-box (the strides kept) as the host reads it
  const std::int64_t global[3] = {40, 30, 20}, offset[3] = {5, 3, 7}, n[3] = {13, 11, 9};
  std::vector<double> host(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  for (std::size_t q = 0; q < host.size(); ++q) host[q] = std::sin(0.37 * static_cast<double>(q)) * 100.0;
  host[5] = std::nan("");
  host[77] = INFINITY;
  host[300] = -INFINITY;
  host[301] = -0.0;
  const DeviceArray dev(host.data(), host.size() * sizeof(double));
  FieldView hv;
  hv.dtype = DType::Float64;
  for (int a = 0; a < 3; ++a) hv.dims[a] = n[a];
  hv.byte_strides[0] = sizeof(double);
  hv.byte_strides[1] = -static_cast<std::int64_t>(sizeof(double)) * n[0];  // y backwards
  hv.byte_strides[2] = static_cast<std::int64_t>(sizeof(double)) * n[0] * n[1];
  hv.data = host.data() + (n[1] - 1) * n[0];
  const FieldView dv = rebased(hv, host.data(), dev.p);
  for (const int edge : {1, 4, 8}) {
    const std::int64_t origin[3] = {0, 0, 0};
    tessera::FieldSummary::Parts h = tessera::FieldSummary::partial(FieldView{}, origin, global, edge);
    tessera::FieldSummary::Parts d = h;
    tessera::FieldSummary::accumulate(h, hv, offset, global, edge);
    tessera::cuda_field_summary_accumulate(d, dv, offset, global, edge);
    CHECK(d.nan == h.nan);
    CHECK(d.vmin == h.vmin);
    CHECK(d.vmax == h.vmax);
    CHECK(std::memcmp(d.lo.data(), h.lo.data(), h.lo.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(d.hi.data(), h.hi.data(), h.hi.size() * sizeof(double)) == 0);
    CHECK(d.flags == h.flags);
  }
  FieldView hs = hv, ds = dv;
  for (FieldView* v : {&hs, &ds}) {
    v->data = static_cast<const unsigned char*>(v->data) + 2 * v->byte_strides[0] + 3 * v->byte_strides[1] +
              v->byte_strides[2];
    v->dims[0] = 7;
    v->dims[1] = 5;
    v->dims[2] = 4;
  }
  std::vector<double> from_device(140), from_host(140);
  tessera::cuda_copy_box_to_host(from_device.data(), ds);
  tessera::cuda_copy_box_to_host(from_host.data(), hs);
  CHECK(std::memcmp(from_device.data(), from_host.data(), from_host.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(&from_host[0], static_cast<const double*>(hs.data), sizeof(double)) == 0);
}

TEST_CASE("GPU: one rank's host and device blocks assembled on the device are the host's field bit for bit",
          "[gpu][memory]") {
  // A 12x10x9 float32 field in three slabs along z: a dense device block, a host block inside
  // a ghosted array (its rows x-contiguous: copied straight from it), and a host block stored
  // y-backwards (packed on the host first); the replica copied back equals the field, and the
  // host blocks' bytes are what crossed
  const std::int64_t g[3] = {12, 10, 9}, nx = g[0], ny = g[1];
  std::vector<float> whole(static_cast<std::size_t>(g[0] * g[1] * g[2]));
  for (std::size_t q = 0; q < whole.size(); ++q) whole[q] = static_cast<float>(std::sin(0.11 * static_cast<double>(q)));
  const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return whole[static_cast<std::size_t>((k * ny + j) * nx + i)];
  };
  const std::int64_t slab = 3, e = sizeof(float);
  // Slab 0: device, dense
  const DeviceArray dev(whole.data(), static_cast<std::size_t>(nx * ny * slab * e));
  FieldView a = FieldView::contiguous(dev.p, DType::Float32, nx, ny, slab);
  // Slab 1: host, one ghost layer on every side of a (nx+2) x (ny+2) x (slab+2) array
  std::vector<float> ghosted(static_cast<std::size_t>((nx + 2) * (ny + 2) * (slab + 2)), -1.0f);
  for (std::int64_t k = 0; k < slab; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        ghosted[static_cast<std::size_t>(((k + 1) * (ny + 2) + j + 1) * (nx + 2) + i + 1)] = at(i, j, slab + k);
  FieldView b;
  b.dtype = DType::Float32;
  b.dims[0] = nx;
  b.dims[1] = ny;
  b.dims[2] = slab;
  b.byte_strides[0] = e;
  b.byte_strides[1] = e * (nx + 2);
  b.byte_strides[2] = e * (nx + 2) * (ny + 2);
  b.data = ghosted.data() + ((ny + 2) + 1) * (nx + 2) + 1;
  // Slab 2: host, y stored backwards
  std::vector<float> backwards(static_cast<std::size_t>(nx * ny * slab));
  for (std::int64_t k = 0; k < slab; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        backwards[static_cast<std::size_t>((k * ny + (ny - 1 - j)) * nx + i)] = at(i, j, 2 * slab + k);
  FieldView c = b;
  c.byte_strides[1] = -e * nx;
  c.byte_strides[2] = e * nx * ny;
  c.data = backwards.data() + (ny - 1) * nx;
  for (const FieldView* v : {&a, &b, &c}) v->validate("block");
  const std::vector<FieldView> blocks = {a, b, c};
  const std::vector<std::array<std::int64_t, 3>> offsets = {{0, 0, 0}, {0, 0, slab}, {0, 0, 2 * slab}};
  const tessera::DeviceReplica r = tessera::cuda_assemble_on_device(blocks, offsets, g, DType::Float32, nullptr,
                                                                    std::uint64_t{1} << 30, "a test's limit");
  CHECK(r.bytes_to_device == static_cast<std::uint64_t>(2 * nx * ny * slab * e));
  CHECK(tessera::cuda_memory_kind(r.view.data) == MemoryKind::Device);
  std::vector<float> back(whole.size());
  tessera::cuda_copy_to_host(back.data(), r.view.data, back.size() * sizeof(float));
  CHECK(std::memcmp(back.data(), whole.data(), whole.size() * sizeof(float)) == 0);
  // No device block: refused by name (the host assembles such a field)
  const std::vector<FieldView> host_only = {b, c};
  const std::vector<std::array<std::int64_t, 3>> two = {{0, 0, 0}, {0, 0, slab}};
  const std::int64_t g2[3] = {nx, ny, 2 * slab};
  CHECK_THROWS_WITH(
      tessera::cuda_assemble_on_device(host_only, two, g2, DType::Float32, nullptr, std::uint64_t{1} << 30, "a limit"),
      Catch::Contains("no block is device memory"));
}
