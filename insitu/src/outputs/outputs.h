#pragma once
/// Where a render's images go and how they are written: output_dir / pattern + extension,
/// directories created, every file written atomically (temporary file + rename), so a reader
/// (or a crash) never sees half a file under the final name.
#include <tessera/config/render_spec.h>
#include <tessera/image.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tessera::insitu {

/// output_dir / format_output_path(output.file, name, step, time, rank), without extension.
std::string output_base(const std::string& output_dir, const config::RenderSpec& spec, std::int64_t step, double time,
                        int rank);

/// Writes `img` as base + ".exr" / ".png" per spec.output.formats (PNG tone-mapped with the
/// output's exposure and curve), creating the parent directory. Appends each path written to
/// `files`, in the order of spec.output.formats. Throws std::runtime_error naming the path and
/// the fault.
/// With `annotations`, they are drawn into the PNG (never the EXR).
void write_image_files(const std::string& base, const config::OutputSpec& output, const Image& img,
                       std::vector<std::string>& files, const AnnotationDesc* annotations = nullptr);

/// Writes `text` to `path` through AtomicOutputFile (every byte checked, nothing under `path`
/// unless complete), creating the parent directory. Throws like the above.
void write_text_atomic(const std::string& path, const std::string& text);

/// Creates `dir` and its parents if missing; throws std::runtime_error naming it on failure.
void ensure_directory(const std::string& dir);

}  // namespace tessera::insitu
