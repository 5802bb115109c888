#include <tessera/image_format.h>

#include <cstddef>

namespace tessera {
namespace {

void write_exr_file(const std::string& path, const Image& image, const ToneMap&, const AnnotationDesc*) {
  write_exr(path, image);
}

void write_png_file(const std::string& path, const Image& image, const ToneMap& tone_map,
                    const AnnotationDesc* annotations) {
  write_png(path, image, tone_map, annotations);
}

/// Row i is ImageFormat i (checked below), so image_format() indexes it.
constexpr ImageFormatInfo kImageFormats[] = {
    {ImageFormat::Exr, "exr", ".exr", false, 0, 2 * 16, write_exr_file},
    {ImageFormat::Png, "png", ".png", true, 4, 0, write_png_file},
};

constexpr bool rows_in_enum_order() {
  for (std::size_t i = 0; i < std::size(kImageFormats); ++i)
    if (kImageFormats[i].value != static_cast<ImageFormat>(i)) return false;
  return true;
}
static_assert(rows_in_enum_order(), "kImageFormats: row i must be ImageFormat i");

}  // namespace

std::span<const ImageFormatInfo> image_formats() { return kImageFormats; }

const ImageFormatInfo& image_format(ImageFormat f) { return kImageFormats[static_cast<std::size_t>(f)]; }

}  // namespace tessera
