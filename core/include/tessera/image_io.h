#pragma once
/// Reading and writing images. Writers go through a temporary file in the same directory and
/// rename it into place, so a crash never leaves a half-written image under the final name.
/// All functions throw std::runtime_error naming the path and the fault. Writers hold
/// BlockWriteSignals (signal_guard.h): a file-size limit or a closed pipe is an error, never
/// a SIGXFSZ / SIGPIPE in the caller; the temporary file is removed on any failure.
#include <tessera/image.h>

#include <cstdint>
#include <string>
#include <utility>

namespace tessera {

/// EXR, float32 channels R G B A, plus "variance" and "samples" when the image has them.
void write_exr(const std::string& path, const Image& img);
/// Reads R G B (A if present, else 1; variance/samples if present) from any EXR OpenEXR reads.
Image read_exr(const std::string& path);
/// Width and height of an EXR's data window, from its header alone (no pixel is read or
/// allocated): for estimating the memory read_exr will need.
std::pair<std::int64_t, std::int64_t> read_exr_size(const std::string& path);

struct ToneMap {
  double exposure = 0.0;   ///< stops: pixel * 2^exposure before tone mapping
  enum class Curve { Clamp, Reinhard, Aces } curve = Curve::Aces;
  /// PNG alpha from A (straight alpha). Default false: opaque, since the rendered radiance
  /// already contains the background.
  bool alpha = false;
};
/// 8-bit sRGB PNG, RGBA (alpha from A when tm.alpha, else opaque). Tone map as documented in docs/physics.md.
void write_png(const std::string& path, const Image& img, const ToneMap& tm = {});

/// Apply exposure + curve + sRGB OETF to one linear value; result in [0, 1].
double tonemap_channel(double v, const ToneMap& tm);

}  // namespace tessera
