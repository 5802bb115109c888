#pragma once
/// The image formats a render writes (`output.formats`): one row per format with its name,
/// file extension and writer. The config parser reads the names from this table, and the CLI
/// and the in situ adapter both name and write their files through it, so a new format is
/// one row here (plus its ImageFormat value).
#include <tessera/config/render_spec.h>
#include <tessera/image.h>

#include <span>
#include <string>

namespace tessera::config {

struct OutputFormat {
  const char* name;       ///< as written in `output.formats`: "exr"
  ImageFormat value;
  const char* extension;  ///< lower case, with the dot: ".exr"
  /// Writes `image` to `path` in this format, with the render's output options where the
  /// format has any (PNG: output.tone_map(); EXR: linear, with the channels the image has).
  /// Atomic and signal-safe like every writer of image_io.h; throws std::runtime_error naming
  /// the path and the fault.
  void (*write)(const std::string& path, const Image& image, const OutputSpec& output);
};

/// Every format, in the order messages list them (exr, png). Valid for the whole program.
std::span<const OutputFormat> output_formats();
/// The row of `f`.
const OutputFormat& output_format(ImageFormat f);

}  // namespace tessera::config
