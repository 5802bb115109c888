#include "io/exr_header.h"

#include <tessera/image_io.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::detail {
namespace {

constexpr unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr std::uint32_t kFlagTiled = 0x200, kFlagLongNames = 0x400, kFlagDeep = 0x800, kFlagMultiPart = 0x1000;

[[noreturn]] void bad(const std::string& what) { throw std::runtime_error(what); }

std::int32_t le32(const unsigned char* p) {
  return static_cast<std::int32_t>(std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                                   std::uint32_t(p[3]) << 24);
}

/// Reads the header front to back, never past the end of the file.
class Cursor {
 public:
  explicit Cursor(const RegularFile& f) : m_file(f) {}
  std::uint64_t pos() const { return m_pos; }
  std::uint64_t left() const { return m_file.size() - m_pos; }
  void read(void* out, std::size_t n) {
    if (n > left()) bad("header ends early: the file has " + std::to_string(m_file.size()) + " bytes");
    m_file.read_at(m_pos, out, n);
    m_pos += n;
  }
  std::int32_t i32() {
    unsigned char b[4];
    read(b, 4);
    return le32(b);
  }
  /// A NUL-terminated name of at most `max_len` characters.
  std::string name(std::size_t max_len) {
    std::string s;
    for (;;) {
      char c = 0;
      read(&c, 1);
      if (c == '\0') return s;
      if (s.size() == max_len) bad("header attribute name longer than " + std::to_string(max_len) + " characters");
      s += c;
    }
  }

 private:
  const RegularFile& m_file;
  std::uint64_t m_pos = 0;
};

/// Bytes per pixel of a channel list value: name\0, int32 type, 4 bytes, int32 xs, int32 ys.
double channel_bytes(const std::vector<unsigned char>& v) {
  double bytes = 0.0;
  std::size_t i = 0;
  while (i < v.size() && v[i] != 0) {
    while (i < v.size() && v[i] != 0) ++i;  // name
    ++i;
    if (i + 16 > v.size()) bad("malformed channel list");
    const std::int32_t type = le32(&v[i]), xs = le32(&v[i + 8]), ys = le32(&v[i + 12]);
    if (type < 0 || type > 2 || xs < 1 || ys < 1) bad("malformed channel list");
    bytes += (type == 1 ? 2.0 : 4.0) / (double(xs) * double(ys));
    i += 16;
  }
  return bytes;
}

/// Scanlines per chunk of each compression id (OpenEXR: NO, RLE, ZIPS, ZIP, PIZ, PXR24, B44,
/// B44A, DWAA, DWAB); 0 for ids OpenEXR does not know.
int lines_per_chunk(int compression) {
  constexpr int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return compression >= 0 && compression < 10 ? kLines[compression] : 0;
}

std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

}  // namespace

ExrHeaderSummary check_exr_header(const RegularFile& file) {
  Cursor c(file);

  // Magic number and version flags: one part, flat (not deep) images only
  unsigned char magic[4];
  c.read(magic, 4);
  if (std::memcmp(magic, kMagic, 4) != 0) bad("not an OpenEXR file (wrong magic number)");
  const auto flags = static_cast<std::uint32_t>(c.i32());
  if ((flags & 0xff) != 2) bad("unsupported OpenEXR version " + std::to_string(flags & 0xff));
  if (flags & (kFlagDeep | kFlagMultiPart))
    bad("multi-part or deep EXR (allowed: a single-part scanline or tiled image)");
  const std::size_t max_name = (flags & kFlagLongNames) ? 255 : 31;

  // Attributes: every declared size must fit in what is left of the file
  ExrHeaderSummary s;
  bool have_window = false, have_channels = false, have_tiles = false;
  std::int64_t tile_w = 0, tile_h = 0;
  for (;;) {
    const std::string name = c.name(max_name);
    if (name.empty()) break;
    const std::string type = c.name(max_name);
    const std::int32_t size = c.i32();
    if (size < 0 || std::uint64_t(size) > c.left()) {
      bad("header attribute \"" + name + "\" declares " + std::to_string(size) + " bytes but the file has " +
          std::to_string(c.left()) + " left");
    }
    if (name == "dataWindow" && type == "box2i" && size == 16) {
      const std::int64_t x0 = c.i32(), y0 = c.i32(), x1 = c.i32(), y1 = c.i32();
      s.width = x1 - x0 + 1;
      s.height = y1 - y0 + 1;
      have_window = true;
    } else if (name == "channels" && type == "chlist") {
      std::vector<unsigned char> v(static_cast<std::size_t>(size));
      c.read(v.data(), v.size());
      s.bytes_per_pixel = channel_bytes(v);
      have_channels = true;
    } else if (name == "tiles" && type == "tiledesc" && size == 9) {
      tile_w = static_cast<std::uint32_t>(c.i32());
      tile_h = static_cast<std::uint32_t>(c.i32());
      unsigned char mode = 0;
      c.read(&mode, 1);
      have_tiles = true;
    } else if (name == "compression" && type == "compression" && size == 1) {
      unsigned char b = 0;
      c.read(&b, 1);
      s.compression = b;
    } else {
      std::vector<unsigned char> skip(std::min<std::size_t>(std::size_t(size), 4096));
      for (std::int32_t left = size; left > 0;) {
        const std::size_t n = std::min<std::size_t>(std::size_t(left), skip.size());
        c.read(skip.data(), n);
        left -= static_cast<std::int32_t>(n);
      }
    }
  }
  if (!have_window) bad("header has no dataWindow");
  if (!have_channels || s.bytes_per_pixel <= 0.0) bad("header has no channels");

  // The data window against the documented maxima and against what the file can hold
  const std::string size_text = std::to_string(s.width) + "x" + std::to_string(s.height);
  if (s.width < 1 || s.height < 1) bad("data window " + size_text + " is empty");
  if (s.width > kMaxExrEdge || s.height > kMaxExrEdge || s.width * s.height > kMaxExrPixels) {
    bad("data window " + size_text + " is too large (allowed: at most " + std::to_string(kMaxExrEdge) +
        " pixels per side and " + std::to_string(kMaxExrPixels) + " pixels in all)");
  }
  const double pixel_bytes = double(s.width) * double(s.height) * s.bytes_per_pixel;
  const double ratio = s.compression == 0 ? 1.0 : kMaxExrCompression;
  if (pixel_bytes > ratio * double(file.size())) {
    bad("data window " + size_text + " needs " + std::to_string(std::uint64_t(pixel_bytes)) +
        " bytes of pixels but the file has " + std::to_string(file.size()) + " bytes (allowed: " +
        (s.compression == 0 ? std::string("as many bytes as pixel data, the file is uncompressed")
                            : "at most " + std::to_string(int(kMaxExrCompression)) + " times the file size") +
        ")");
  }
  // The chunk offset table (8 bytes a chunk, level 0 counted) must fit in the file; OpenEXR
  // allocates it, and a tile buffer, from the header alone
  const int lines = lines_per_chunk(s.compression);
  if (lines == 0) bad("unknown compression " + std::to_string(s.compression));
  std::int64_t chunks = ceil_div(s.height, lines);
  if (flags & kFlagTiled) {
    if (!have_tiles) bad("tiled file without a tile description");
    if (tile_w < 1 || tile_h < 1 || tile_w > kMaxExrEdge || tile_h > kMaxExrEdge ||
        double(tile_w) * double(tile_h) * s.bytes_per_pixel > kMaxExrCompression * double(file.size())) {
      bad("tile size " + std::to_string(tile_w) + "x" + std::to_string(tile_h) + " does not fit a file of " +
          std::to_string(file.size()) + " bytes (allowed: at most " + std::to_string(kMaxExrEdge) + " per side and " +
          std::to_string(int(kMaxExrCompression)) + " times the file size in bytes)");
    }
    chunks = ceil_div(s.width, tile_w) * ceil_div(s.height, tile_h);
  }
  if (double(chunks) * 8.0 > double(file.size())) {
    bad("data window " + size_text + " needs " + std::to_string(chunks) + " chunks but a file of " +
        std::to_string(file.size()) + " bytes cannot hold their offset table");
  }
  return s;
}

}  // namespace tessera::detail
