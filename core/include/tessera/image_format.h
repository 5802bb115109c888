#pragma once
/// The image formats a render writes: one row per format with its name, file extension,
/// writer, what the writer allocates beside the image, and whether viewers show the file as
/// it is. The config parser reads the names from this table (`output.formats`), the CLI and
/// the in situ adapter name and write their files through it, the memory estimate
/// (memory_estimate.h) counts each format's buffers from it, and the adapter's Cinema index
/// picks the file it lists from it: a new format is one row here plus its ImageFormat value.
#include <tessera/image.h>
#include <tessera/image_io.h>

#include <cstdint>
#include <span>
#include <string>

namespace tessera {

enum class ImageFormat { Exr, Png };

struct ImageFormatInfo {
  ImageFormat value;
  const char* name;       ///< lower case, as configs and messages spell it: "exr"
  const char* extension;  ///< lower case, with the dot: ".exr"
  /// An 8-bit picture that image viewers (browsers, Cinema viewers) show as it is (PNG); a
  /// linear float image (EXR) needs a tone map first.
  bool shown_as_is;
  /// The writer's own copy of the image, bytes per pixel (PNG: its 8-bit RGBA rows).
  std::uint64_t copy_bytes_per_pixel;
  /// The writer's buffers, in scanlines of every float channel it writes (EXR: OpenEXR's
  /// 16-scanline blocks, raw and compressed: 32).
  std::uint64_t buffered_scanlines;
  /// Writes `image` to `path` in this format (PNG through `tone_map`, with `annotations`
  /// drawn when not null; EXR linear, with the channels the image has, never annotated).
  /// Atomic and signal-safe like every writer of image_io.h; throws std::runtime_error naming
  /// the path and the fault.
  void (*write)(const std::string& path, const Image& image, const ToneMap& tone_map,
                const AnnotationDesc* annotations);
};

/// Every format, in the order messages list them (exr, png). Valid for the whole program.
std::span<const ImageFormatInfo> image_formats();
/// The row of `f`.
const ImageFormatInfo& image_format(ImageFormat f);

}  // namespace tessera
