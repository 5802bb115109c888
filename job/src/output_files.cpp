#include <tessera/job/output_files.h>

#include <tessera/config/output_path.h>
#include <tessera/image_format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

namespace tessera::job {
namespace fs = std::filesystem;

namespace {

/// The format an explicit extension names (any case), if any.
std::optional<ImageFormat> format_of_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const ImageFormatInfo& f : image_formats())
    if (ext == f.extension) return f.value;
  return std::nullopt;
}

}  // namespace

std::vector<OutputTarget> output_targets(const config::GlobalOptions& global, const config::RenderSpec& spec,
                                         const std::optional<std::string>& out_flag, bool several, std::int64_t step,
                                         double time) {
  std::vector<OutputTarget> targets;
  if (!out_flag) {
    const fs::path stem =
        fs::path(global.output_dir) / config::format_output_path(spec.output.file, spec.name, step, time, 0);
    for (const ImageFormat f : spec.output.formats) targets.push_back({stem.string() + image_format(f).extension, f});
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
  for (const ImageFormat f : spec.output.formats) targets.push_back({out.string() + image_format(f).extension, f});
  return targets;
}

void write_outputs(const std::vector<OutputTarget>& targets, const Image& image, const config::OutputSpec& output,
                   const AnnotationDesc* annotations) {
  for (const OutputTarget& t : targets) {
    const fs::path p(t.path);
    if (p.has_parent_path()) {
      std::error_code ec;
      fs::create_directories(p.parent_path(), ec);
      if (ec) throw std::runtime_error("cannot create directory " + p.parent_path().string() + ": " + ec.message());
    }
    image_format(t.format).write(t.path, image, output.tone_map(), annotations);
  }
}

}  // namespace tessera::job
