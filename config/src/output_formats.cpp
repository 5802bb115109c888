#include <tessera/config/output_formats.h>

#include <tessera/image_io.h>

#include <iterator>

namespace tessera::config {
namespace {

void write_exr_file(const std::string& path, const Image& image, const OutputSpec&) {
  write_exr(path, image);
}

void write_png_file(const std::string& path, const Image& image, const OutputSpec& output) {
  write_png(path, image, output.tone_map());
}

constexpr OutputFormat kOutputFormats[] = {
    {"exr", ImageFormat::Exr, ".exr", write_exr_file},
    {"png", ImageFormat::Png, ".png", write_png_file},
};

}  // namespace

std::span<const OutputFormat> output_formats() { return kOutputFormats; }

const OutputFormat& output_format(ImageFormat f) {
  for (const OutputFormat& row : kOutputFormats)
    if (row.value == f) return row;
  return kOutputFormats[0];  // unreachable: every ImageFormat has a row
}

const char* format_name(ImageFormat f) { return output_format(f).name; }

}  // namespace tessera::config
