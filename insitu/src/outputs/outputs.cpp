#include "outputs/outputs.h"

#include <tessera/atomic_output.h>
#include <tessera/config/output_path.h>
#include <tessera/image_format.h>

#include <filesystem>
#include <stdexcept>

namespace tessera::insitu {
namespace fs = std::filesystem;

std::string output_base(const std::string& output_dir, const config::RenderSpec& spec, std::int64_t step, double time,
                        int rank) {
  const std::string rel = config::format_output_path(spec.output.file, spec.name, step, time, rank);
  return (fs::path(output_dir) / rel).string();
}

void ensure_directory(const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error("cannot create directory '" + dir +
                             "': " + (ec ? ec.message() : std::string("not a directory")));
}

void write_image_files(const std::string& base, const config::OutputSpec& output, const Image& img,
                       std::vector<std::string>& files, const AnnotationDesc* annotations) {
  ensure_directory(fs::path(base).parent_path().string());
  for (const ImageFormat f : output.formats) {
    const ImageFormatInfo& format = image_format(f);
    const std::string path = base + format.extension;
    format.write(path, img, output.tone_map(), annotations);
    files.push_back(path);
  }
}

void write_text_atomic(const std::string& path, const std::string& text) {
  ensure_directory(fs::path(path).parent_path().string());
  write_file_atomically(path, text);
}

}  // namespace tessera::insitu
