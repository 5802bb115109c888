#pragma once
/// Reading and writing images. Writers go through AtomicOutputFile (atomic_output.h): a
/// temporary file in the same directory, every byte checked, verified, then renamed into place,
/// so neither a crash nor a full disk, quota or file-size limit ever leaves a half-written
/// image under the final name (an older image there stays until the new one is complete).
/// All functions throw std::runtime_error naming the path and the fault. Writers hold
/// BlockWriteSignals (signal_guard.h): a file-size limit or a closed pipe is an error, never
/// a SIGXFSZ / SIGPIPE in the caller; the temporary file is removed on any failure.
#include <tessera/image.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tessera {

struct AnnotationDesc;  // annotate.h

/// EXR, float32 channels R G B A, plus "variance", "samples" and the layer "denoised.R/G/B"
/// when the image has them (R G B A stay the unbiased estimate).
void write_exr(const std::string& path, const Image& img);
/// Reads R G B (A if present, else 1; variance/samples/denoised.R/G/B if present) from a single-part,
/// non-deep scanline or tiled EXR. `path` must be a regular file (a FIFO or a device is
/// refused without blocking). Before anything is allocated the header is checked:
/// - data window at most kMaxExrEdge pixels on each side and kMaxExrPixels in all;
/// - uncompressed pixel bytes at most the file size (no compression) or kMaxExrCompression
///   times the file size (any compression; deflate itself cannot exceed 1032:1);
/// - the chunk offset table (8 bytes per scanline block or level-0 tile) fits in the file, and
///   a tile is at most kMaxExrEdge per side and kMaxExrCompression times the file size;
/// - every header attribute fits in the file.
/// OpenEXR's own exceptions (corrupt data, truncated files) come out as std::runtime_error.
Image read_exr(const std::string& path);
/// The data window size read_exr would return, from the header alone (the same checks, no
/// pixel allocation): for estimating memory before reading. Throws like read_exr.
struct ExrSize {
  int width = 0, height = 0;
};
ExrSize read_exr_size(const std::string& path);
inline constexpr std::int64_t kMaxExrEdge = 16384;
inline constexpr std::int64_t kMaxExrPixels = std::int64_t(1) << 27;  ///< 16384 x 8192
inline constexpr double kMaxExrCompression = 1100.0;

struct ToneMap {
  double exposure = 0.0;  ///< stops: pixel * 2^exposure before tone mapping
  enum class Curve { Clamp, Reinhard, Aces } curve = Curve::Aces;
  /// PNG alpha from A (straight alpha). Default false: opaque, since the rendered radiance
  /// already contains the background.
  bool alpha = false;
};
/// 8-bit sRGB PNG, RGBA (alpha from A when tm.alpha, else opaque); RGB from img.denoised
/// when the image has it. Tone map as documented in docs/physics.md. With `annotations`, they
/// are drawn into the 8-bit pixels after the tone map (annotate.h); a font that cannot be
/// loaded throws before anything is written.
void write_png(const std::string& path, const Image& img, const ToneMap& tm = {},
               const AnnotationDesc* annotations = nullptr);

/// The 8-bit RGBA pixels write_png encodes (before any annotation), width*height*4 bytes,
/// row 0 at the top. Throws std::invalid_argument when the buffers do not match the size.
std::vector<std::uint8_t> png_pixels(const Image& img, const ToneMap& tm = {});

/// Apply exposure + curve + sRGB OETF to one linear value; result in [0, 1].
double tonemap_channel(double v, const ToneMap& tm);

}  // namespace tessera
