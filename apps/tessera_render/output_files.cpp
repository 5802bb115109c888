#include "output_files.h"

#include <tessera/config/output_path.h>
#include <tessera/image_io.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

namespace tessera::cli {
namespace fs = std::filesystem;
using config::ImageFormat;

namespace {

/// The format an explicit extension names, if any.
std::optional<ImageFormat> format_of_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".exr") return ImageFormat::Exr;
  if (ext == ".png") return ImageFormat::Png;
  return std::nullopt;
}

}  // namespace

std::vector<OutputTarget> output_targets(const config::GlobalOptions& global,
                                         const config::RenderSpec& spec,
                                         const std::optional<std::string>& out_flag, bool several) {
  std::vector<OutputTarget> targets;
  if (!out_flag) {
    const fs::path stem = fs::path(global.output_dir) /
                          config::format_output_path(spec.output.file, spec.name, 0, 0.0, 0);
    for (const ImageFormat f : spec.output.formats)
      targets.push_back({stem.string() + config::format_extension(f), f});
    return targets;
  }

  fs::path out(*out_flag);
  const std::optional<ImageFormat> explicit_format = format_of_extension(out);
  if (explicit_format) {
    std::string ext = out.extension().string();
    fs::path base = out;
    base.replace_extension();
    if (several) base += "_" + spec.name;
    targets.push_back({base.string() + ext, *explicit_format});
    return targets;
  }
  if (several) out += "_" + spec.name;
  for (const ImageFormat f : spec.output.formats)
    targets.push_back({out.string() + config::format_extension(f), f});
  return targets;
}

void write_outputs(const std::vector<OutputTarget>& targets, const Image& image,
                   const config::OutputSpec& output) {
  for (const OutputTarget& t : targets) {
    const fs::path p(t.path);
    if (p.has_parent_path()) {
      std::error_code ec;
      fs::create_directories(p.parent_path(), ec);
      if (ec) throw std::runtime_error("cannot create directory " + p.parent_path().string() + ": " + ec.message());
    }
    if (t.format == ImageFormat::Exr) write_exr(t.path, image);
    else write_png(t.path, image, output.tone_map());
  }
}

}  // namespace tessera::cli
