#pragma once
/// Estimates of one render's own allocations, checked against a per-rank memory limit before
/// any of them is made (docs/insitu.md and docs/cli.md, "Limits and failure").
///
/// The estimate counts what the render allocates, not the caller's data: the film (double
/// accumulators per pixel), the resolved image and the bytes the writers add, the tile and
/// work lists, the macrocell summary and majorants, the environment map and its sampling
/// tables. Callers add their own parts (the adapter: the MPI field replica) with add().
/// Figures are upper estimates from the element sizes; small fixed costs (a few KiB per
/// thread) are left out.
#include <tessera/image_format.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tessera {

/// What core needs to know of one render to estimate its allocations.
struct RenderFootprint {
  int width = 0, height = 0;  ///< image size in pixels
  int tile = 8;               ///< tile edge (0 = scanline), as RenderOptions::tile
  int threads = 1;            ///< worker threads (> 0)
  bool variance = false;      ///< the resolved image has a variance layer
  bool samples = false;       ///< the resolved image has a sample-count layer
  /// image.denoise: the film's auxiliary sums (AuxSums per pixel), and where the image is
  /// written the albedo, normal and denoised layers (3 floats per pixel each) and OIDN's
  /// working memory (kDenoiserBytesPerPixel up to kDenoiserMaxWorkingBytes, and
  /// kDenoiserFixedBytes)
  bool denoise = false;
  /// Formats written, no repeats (where this rank writes: rank 0, or the CLI); each adds the
  /// buffers its row of image_format.h names
  std::vector<ImageFormat> formats{ImageFormat::Exr, ImageFormat::Png};
  bool writes = true;                      ///< this rank resolves and writes the image
  bool keeps_last_image = false;           ///< the image is kept after the write (adapter rank 0)
  int views = 0;                           ///< Cinema views rendered after the main image (0 = none)
  std::int64_t field_dims[3] = {0, 0, 0};  ///< vertices of the rendered field; 0 = not counted
  int macrocell_edge = 16;                 ///< majorant_edge() of the field and integrator
  /// Rectilinear axes of the field (VolumeGeometry::coords set): each adds its lookup tables,
  /// at most 4 (field_dims[a] - 1) + 65 bin entries and a wall per macrocell (8 bytes each)
  bool rectilinear[3] = {false, false, false};
  std::int64_t envmap_width = 0, envmap_height = 0;  ///< envmap texels; 0 = no envmap
  /// Rendered by the CUDA backend (RenderOptions::device): a call's host copies of its pixels
  /// (where each is, its sums back from the device, its auxiliary sums with `denoise`),
  /// kGpuHostBytesPerPixel (+ sizeof(AuxSums)) per pixel, beside the film. Device memory is
  /// checked apart, against the same limit, by the backend.
  bool gpu = false;
  /// With `gpu`: adaptive sampling (image.target_error > 0), whose call holds the pilot pass's
  /// copies and the second pass's at once for a moment: twice the copies above, plus a
  /// sample count and an index (12 bytes) per pixel.
  bool adaptive = false;
};

/// A CUDA call's host bytes per pixel without auxiliary sums: its pixel list (x, y, culled)
/// and the sums copied back from the device (docs/gpu.md).
inline constexpr std::uint64_t kGpuHostBytesPerPixel = 3 * sizeof(int) + 64;

/// A distributed (paged) field rendered by the CUDA backend: the host's bookkeeping of the
/// device's pool per brick of the cut (the directory's host copy, arrival and use stamps, use
/// marks read back, a guess flag; cuda/device_bricks.h), beside one slot's fill buffer.
inline constexpr std::uint64_t kGpuHostBytesPerBrick = 26;

/// Open Image Denoise's own working memory per pixel (its RT filter's tensors and scratch),
/// an upper estimate: the peak RSS growth of denoised CLI renders, less the image and
/// auxiliary buffers counted apart, is about 576 bytes per pixel from 256x256 to 2048x1024
/// (OIDN 2.5.1, CPU device; docs/insitu.md, "Limits and failure"), plus a margin.
inline constexpr std::uint64_t kDenoiserBytesPerPixel = 640;
/// The scratch memory OIDN's filter is allowed (its maxMemoryMB, set by denoise()): a larger
/// image is denoised in overlapping tiles, so OIDN's working memory stops growing (about
/// 1.8 GiB measured at 4096x2048). Below about 3.5 million pixels it does not tile.
inline constexpr int kDenoiserMaxMemoryMB = 2048;
/// The most the per-pixel term counts: OIDN's working memory at that cap, with a margin.
inline constexpr std::uint64_t kDenoiserMaxWorkingBytes = std::uint64_t(2560) << 20;
/// Open Image Denoise's fixed cost once loaded: its libraries, the CPU device and the
/// filter's weights (about 8 MiB measured), with a margin.
inline constexpr std::uint64_t kDenoiserFixedBytes = std::uint64_t(32) << 20;

struct MemoryEstimate {
  struct Part {
    std::string name;
    std::uint64_t bytes;
  };
  std::vector<Part> parts;  ///< in the order added; zero-byte parts are not listed

  void add(std::string name, std::uint64_t bytes);
  std::uint64_t total() const;
  /// "21.3 GiB (film 14 GiB, images 6 GiB, ...)": the total, then each part.
  std::string describe() const;
};

/// The render's own allocations on this rank (saturating: never wraps).
MemoryEstimate estimate_render_memory(const RenderFootprint& f);

/// Bytes short: 512 B, 3.5 KiB, 21.3 GiB (three significant digits).
std::string format_bytes(std::uint64_t bytes);

/// Physical memory of the machine in bytes (sysconf), 0 if unknown.
std::uint64_t physical_memory_bytes();

/// The default per-rank limit: half of physical memory divided by the number of ranks on this
/// node (ranks_on_node >= 1); 4 GiB if physical memory is unknown.
std::uint64_t default_memory_limit_bytes(int ranks_on_node);

}  // namespace tessera
