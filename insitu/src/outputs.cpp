#include "outputs.h"

#include <tessera/config/output_formats.h>
#include <tessera/config/output_path.h>
#include <tessera/signal_guard.h>
#include <tessera/temp_file.h>


#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace tessera::insitu {
namespace fs = std::filesystem;

std::string output_base(const std::string& output_dir, const config::RenderSpec& spec,
                        std::int64_t step, double time, int rank) {
  const std::string rel = config::format_output_path(spec.output.file, spec.name, step, time, rank);
  return (fs::path(output_dir) / rel).string();
}

void ensure_directory(const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error("cannot create directory '" + dir + "': " +
                             (ec ? ec.message() : std::string("not a directory")));
}

void write_image_files(const std::string& base, const config::OutputSpec& output,
                       const Image& img, std::vector<std::string>& files) {
  ensure_directory(fs::path(base).parent_path().string());
  for (const config::ImageFormat f : output.formats) {
    const config::OutputFormat& format = config::output_format(f);
    const std::string path = base + format.extension;
    format.write(path, img, output);
    files.push_back(path);
  }
}

void write_text_atomic(const std::string& path, const std::string& text) {
  ensure_directory(fs::path(path).parent_path().string());
  const BlockWriteSignals no_signals;  // EFBIG / EPIPE, never SIGXFSZ / SIGPIPE
  // A new file beside it (temp_file.h): a FIFO or a link already under the name is not opened
  std::string tmp;
  try {
    tmp = create_temp_file_beside(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write '" + path + "': " + e.what());
  }
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (out) out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) {
      const std::string fault = std::strerror(errno);
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write '" + path + "': " + fault);
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot write '" + path + "': " + ec.message());
  }
}

}  // namespace tessera::insitu
