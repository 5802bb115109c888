// FreeType faces and text rasterisation for the annotations.
#include "annotate/font.h"

#include <tessera/annotate.h>
#include <tessera/message_text.h>

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <stdexcept>

namespace tessera::annotate {
namespace {

int ceil_26_6(long v) { return static_cast<int>((v + 63) >> 6); }

}  // namespace

std::vector<char32_t> decode_utf8(const std::string& s, std::size_t max_points) {
  std::vector<char32_t> out;
  for (std::size_t i = 0; i < s.size() && out.size() < max_points;) {
    const Utf8Char c = next_utf8_char(s, i);  // U+FFFD for each maximal invalid subpart
    out.push_back(c.code_point);
    i += c.length;
  }
  return out;
}

Font::Font(const std::string& path) : m_path(path) {
  if (FT_Init_FreeType(&m_library) != 0) throw std::runtime_error("cannot start FreeType to draw annotations");
  const FT_Error err = FT_New_Face(m_library, path.c_str(), 0, &m_face);
  if (err != 0) {
    FT_Done_FreeType(m_library);
    const char* why = FT_Error_String(err);
    throw std::runtime_error("cannot load font '" + path +
                             "': " + (why ? std::string(why) : "FreeType error " + std::to_string(err)) +
                             " (allowed: a TrueType or OpenType font file)");
  }
  if (!FT_IS_SCALABLE(m_face)) {
    FT_Done_Face(m_face);
    FT_Done_FreeType(m_library);
    throw std::runtime_error("cannot use font '" + path + "': not a scalable font (allowed: TrueType or OpenType)");
  }
  set_pixel_size(16);
}

Font::~Font() {
  FT_Done_Face(m_face);
  FT_Done_FreeType(m_library);
}

void Font::set_pixel_size(int px) {
  px = std::clamp(px, 1, 4096);
  if (FT_Set_Pixel_Sizes(m_face, 0, static_cast<FT_UInt>(px)) != 0)
    throw std::runtime_error("font '" + m_path + "': cannot set a size of " + std::to_string(px) + " pixels");
  m_ascent = ceil_26_6(m_face->size->metrics.ascender);
  m_descent = ceil_26_6(-m_face->size->metrics.descender);
}

TextMask Font::render(const std::string& utf8, int max_width) const {
  // Pass 1: rasterise each glyph once, keeping its bitmap and pen position
  struct Placed {
    int x = 0, y = 0, w = 0, h = 0;
    std::vector<std::uint8_t> bits;
  };
  std::vector<Placed> glyphs;
  const std::vector<char32_t> points = decode_utf8(utf8, kMaxAnnotationGlyphs);
  const bool kerning = FT_HAS_KERNING(m_face);
  long pen = 0;  // 26.6
  FT_UInt previous = 0;
  int right = 0;
  for (const char32_t cp : points) {
    FT_UInt index = FT_Get_Char_Index(m_face, cp);
    if (index == 0) index = FT_Get_Char_Index(m_face, 0xfffd);
    if (kerning && previous != 0 && index != 0) {
      FT_Vector delta;
      if (FT_Get_Kerning(m_face, previous, index, FT_KERNING_DEFAULT, &delta) == 0) pen += delta.x;
    }
    if (FT_Load_Glyph(m_face, index, FT_LOAD_RENDER | FT_LOAD_TARGET_NORMAL) != 0) continue;
    const FT_GlyphSlot slot = m_face->glyph;
    const FT_Bitmap& bm = slot->bitmap;
    Placed g;
    g.x = static_cast<int>(pen >> 6) + slot->bitmap_left;
    g.y = m_ascent - slot->bitmap_top;
    g.w = static_cast<int>(bm.width);
    g.h = static_cast<int>(bm.rows);
    const long next = pen + slot->advance.x;
    if (std::max(g.x + g.w, static_cast<int>(next >> 6)) > max_width) break;
    if (bm.pixel_mode == FT_PIXEL_MODE_GRAY && g.w > 0 && g.h > 0) {
      g.bits.resize(static_cast<std::size_t>(g.w) * g.h);
      for (int r = 0; r < g.h; ++r) {
        const unsigned char* row = bm.buffer + static_cast<long>(r) * bm.pitch;
        std::copy(row, row + g.w, g.bits.begin() + static_cast<std::ptrdiff_t>(r) * g.w);
      }
    }
    right = std::max({right, g.x + g.w, static_cast<int>(next >> 6)});
    glyphs.push_back(std::move(g));
    pen = next;
    previous = index;
  }

  // Pass 2: the mask, one line high, glyph coverage combined by max
  TextMask mask;
  mask.width = std::max(0, right);
  mask.height = line_height();
  mask.ascent = m_ascent;
  mask.coverage.assign(static_cast<std::size_t>(mask.width) * mask.height, 0);
  for (const Placed& g : glyphs) {
    for (int r = 0; r < g.h; ++r) {
      const int y = g.y + r;
      if (y < 0 || y >= mask.height) continue;
      for (int c = 0; c < g.w; ++c) {
        const int x = g.x + c;
        if (x < 0 || x >= mask.width) continue;
        std::uint8_t& dst = mask.coverage[static_cast<std::size_t>(y) * mask.width + x];
        dst = std::max(dst, g.bits[static_cast<std::size_t>(r) * g.w + c]);
      }
    }
  }
  return mask;
}

}  // namespace tessera::annotate
