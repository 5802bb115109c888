#pragma once
// Where a render's images go, and writing them.
#include <tessera/config/config.h>
#include <tessera/image.h>
#include <tessera/image_format.h>

#include <optional>
#include <string>
#include <vector>

namespace tessera::job {

struct OutputTarget {
  std::string path;
  ImageFormat format;
};

/// Without -o: output_dir / format_output_path(output.file, name, `step`, `time`, rank 0)
/// plus .exr / .png for each of output.formats.
/// With -o OUT: OUT.exr / OUT.png per output.formats, or only OUT itself when it ends in .exr
/// or .png (any case). With several renders (`several`), _NAME goes before the extension:
/// OUT_NAME.exr.
std::vector<OutputTarget> output_targets(const config::GlobalOptions& global, const config::RenderSpec& spec,
                                         const std::optional<std::string>& out_flag, bool several,
                                         std::int64_t step = 0, double time = 0.0);

/// Writes the image to every target (EXR linear; PNG through the render's tone map, with
/// `annotations` drawn when not null), creating directories as needed.
void write_outputs(const std::vector<OutputTarget>& targets, const Image& image, const config::OutputSpec& output,
                   const AnnotationDesc* annotations = nullptr);

}  // namespace tessera::job
