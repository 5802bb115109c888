#include <tessera/memory_estimate.h>

#include <tessera/field_summary.h>
#include <tessera/film.h>
#include <tessera/stats.h>
#include <tessera/tiles.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <limits>

namespace tessera {
namespace {

using u64 = std::uint64_t;
constexpr u64 kMax = std::numeric_limits<u64>::max();

u64 mul(u64 a, u64 b) { return a != 0 && b > kMax / a ? kMax : a * b; }
u64 sum(u64 a, u64 b) { return b > kMax - a ? kMax : a + b; }
u64 nonneg(std::int64_t v) { return v > 0 ? static_cast<u64>(v) : 0; }

/// A writer's scanline buffers for an image `width` wide with `channels` float channels.
u64 scanline_bytes(const ImageFormatInfo& format, int width, u64 channels) {
  return mul(mul(nonneg(width), channels * sizeof(float)), format.buffered_scanlines);
}

}  // namespace

void MemoryEstimate::add(std::string name, std::uint64_t bytes) {
  if (bytes == 0) return;
  for (Part& p : parts)
    if (p.name == name) {
      p.bytes = sum(p.bytes, bytes);
      return;
    }
  parts.push_back({std::move(name), bytes});
}

std::uint64_t MemoryEstimate::total() const {
  u64 t = 0;
  for (const Part& p : parts) t = sum(t, p.bytes);
  return t;
}

std::string MemoryEstimate::describe() const {
  std::string s = format_bytes(total()) + " (";
  for (std::size_t i = 0; i < parts.size(); ++i)
    s += (i ? ", " : "") + parts[i].name + " " + format_bytes(parts[i].bytes);
  return s + ")";
}

std::string format_bytes(std::uint64_t bytes) {
  static constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
  char buf[32];
  if (u == 0) std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
  else std::snprintf(buf, sizeof buf, "%.3g %s", v, kUnits[u]);
  return buf;
}

std::uint64_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? mul(static_cast<u64>(pages), static_cast<u64>(page)) : 0;
}

std::uint64_t default_memory_limit_bytes(int ranks_on_node) {
  const u64 phys = physical_memory_bytes();
  if (phys == 0) return u64{4} << 30;
  return phys / 2 / static_cast<u64>(std::max(1, ranks_on_node));
}

MemoryEstimate estimate_render_memory(const RenderFootprint& f) {
  MemoryEstimate e;
  const u64 pixels = mul(nonneg(f.width), nonneg(f.height));
  const u64 views = f.views > 0 ? 1 : 0;  // one view's film and image live beside the main ones

  // Film: the double accumulators of every pixel, on every rank (film.h)
  e.add("film", mul(mul(pixels, sizeof(PixelSums)), 1 + views));
  if (f.denoise) e.add("denoise buffers", mul(mul(pixels, sizeof(AuxSums)), 1 + views));

  // Images: the resolved float image (RGBA + layers), the last image kept by the adapter, and
  // each format's writer: its own copy and its scanline buffers (image_format.h: the 8-bit
  // PNG copy, OpenEXR's 16-scanline blocks raw and compressed)
  if (f.writes) {
    const u64 layers = 4 + (f.variance ? 1 : 0) + (f.samples ? 1 : 0);
    const u64 image = mul(pixels, layers * sizeof(float));
    u64 bytes = mul(image, 1 + views + (f.keeps_last_image ? 1 : 0));
    for (const ImageFormat format : f.formats) {
      const ImageFormatInfo& row = image_format(format);
      bytes = sum(bytes, sum(mul(pixels, row.copy_bytes_per_pixel), scanline_bytes(row, f.width, layers)));
    }
    e.add("images", bytes);
    // Denoising: albedo, normal and denoised RGB beside the image, OIDN's working memory,
    // and the writers' buffers for the three denoised channels (the EXR writes them as extra
    // channels; the PNG copy shows them in place of RGB)
    if (f.denoise) {
      u64 d = mul(mul(pixels, 9 * sizeof(float)), 1 + views + (f.keeps_last_image ? 1 : 0));
      d = sum(d, sum(std::min(mul(pixels, kDenoiserBytesPerPixel), kDenoiserMaxWorkingBytes), kDenoiserFixedBytes));
      for (const ImageFormat format : f.formats) d = sum(d, scanline_bytes(image_format(format), f.width, 3));
      e.add("denoise buffers", d);
    }
  }

  // The CUDA backend's host copies of one call's pixels (device_render.cpp): the pixel list and
  // the sums back from the device, one call (view) at a time
  if (f.gpu) {
    const u64 per_pixel = kGpuHostBytesPerPixel + (f.denoise ? static_cast<u64>(sizeof(AuxSums)) : 0);
    e.add("GPU call's host copies", mul(pixels, f.adaptive ? 2 * per_pixel + 12 : per_pixel));
  }

  // Tiles and work lists: the tile list and culling flags (prepare), the tile indices, work
  // items, per-item counters and band counters (render_tiles); a short list is cut into bands
  const u64 edge = f.tile > 0 ? static_cast<u64>(f.tile) : 0;
  const u64 tiles =
      edge ? mul((nonneg(f.width) + edge - 1) / edge, (nonneg(f.height) + edge - 1) / edge) : nonneg(f.height);
  const u64 threads = nonneg(std::max(1, f.threads));
  const u64 items = tiles < 4 * threads ? mul(tiles, std::max<u64>(1, ((edge ? edge : 1) + 7) / 8)) : tiles;
  constexpr u64 kPerTile = sizeof(Tile) + 1 + sizeof(int) + sizeof(std::atomic<int>);
  constexpr u64 kPerItem = sizeof(Tile) + sizeof(std::size_t) + sizeof(RenderStats);
  e.add("tile lists", sum(mul(tiles, kPerTile), mul(items, kPerItem)));

  // Macrocells: the summary's value range and the majorant of each cell (majorant_grid.h)
  if (f.field_dims[0] > 0 && f.field_dims[1] > 0 && f.field_dims[2] > 0) {
    const u64 c = static_cast<u64>(std::max(1, f.macrocell_edge));
    u64 cells = 1;
    for (int a = 0; a < 3; ++a) cells = mul(cells, std::max<u64>(1, (nonneg(f.field_dims[a] - 1) + c - 1) / c));
    e.add("majorant grid", mul(cells, sizeof(CellRange) + sizeof(double) + sizeof(std::uint8_t)));
    // Rectilinear axes: the bin table and macrocell walls of each (axis_tables.h)
    u64 axes = 0;
    for (int a = 0; a < 3; ++a) {
      if (!f.rectilinear[a]) continue;
      const u64 n = nonneg(f.field_dims[a] - 1);
      axes = sum(axes, mul(sum(mul(4, n), 65), sizeof(std::int64_t)));
      axes = sum(axes, mul(std::max<u64>(1, (n + c - 1) / c) + 1, sizeof(double)));
    }
    e.add("axis tables", axes);
  }

  // Environment map: the float image read (RGBA + optional layers), the texels as doubles
  // and the 2D sampling tables (the luminance weights, each row's function and CDF)
  if (f.envmap_width > 0 && f.envmap_height > 0) {
    const u64 texels = mul(nonneg(f.envmap_width), nonneg(f.envmap_height));
    e.add("envmap", mul(texels, 6 * sizeof(float) + 3 * sizeof(double) + 3 * sizeof(double)));
  }
  return e;
}

}  // namespace tessera
