// The image format table (image_format.h): one row per format, found by its value, each
// writer writes what its reader reads, and viewers are shown the PNG.
#include <tessera/image_format.h>
#include <tessera/image_io.h>

#include "temp_dir.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <string>

using namespace tessera;

TEST_CASE("image formats: one row per format, each writer writes what its reader reads", "[image_format]") {
  tessera_test::TempDir dir;
  std::set<std::string> names, extensions;
  Image img;
  img.width = 3;
  img.height = 2;
  img.rgba.assign(3 * 2 * 4, 1.0f);
  img.px(2, 1)[0] = 0.5f;
  for (const ImageFormat f : {ImageFormat::Exr, ImageFormat::Png}) {
    const ImageFormatInfo& row = image_format(f);
    INFO(row.name);
    CHECK(row.value == f);
    CHECK(names.insert(row.name).second);
    CHECK(extensions.insert(row.extension).second);
    CHECK(std::string(row.extension) == std::string(".") + row.name);
    const std::string path = dir.file(std::string("img") + row.extension);
    row.write(path, img, ToneMap{}, nullptr);
    std::ifstream in(path, std::ios::binary);
    std::string head(4, '\0');
    in.read(head.data(), 4);
    if (f == ImageFormat::Exr) {
      const Image back = read_exr(path);
      CHECK(back.width == 3);
      CHECK(back.px(2, 1)[0] == 0.5f);
      CHECK_FALSE(row.shown_as_is);  // linear floats: a viewer needs a tone map
    } else {
      CHECK(head == "\x89PNG");
      CHECK(row.shown_as_is);
    }
  }
  CHECK(image_formats().size() == names.size());
}
