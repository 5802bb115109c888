#pragma once
// Reads a PNG back as 8-bit RGBA (libpng's simplified API), for pixel tests of written files.
#include <catch2/catch.hpp>
#include <png.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tessera_test {

/// The file's pixels, width*height*4 bytes, row 0 at the top; w and h set. REQUIREs success.
inline std::vector<std::uint8_t> read_png_rgba(const std::string& path, int& w, int& h) {
  png_image reader{};
  reader.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&reader, path.c_str()) != 0);
  reader.format = PNG_FORMAT_RGBA;
  std::vector<std::uint8_t> px(PNG_IMAGE_SIZE(reader));
  REQUIRE(png_image_finish_read(&reader, nullptr, px.data(), 0, nullptr) != 0);
  w = static_cast<int>(reader.width);
  h = static_cast<int>(reader.height);
  return px;
}

}  // namespace tessera_test
