#pragma once
// Private: a FreeType face at one pixel size, rasterising a line of UTF-8 text to an 8-bit
// coverage mask (anti-aliased, kerned where the font has kerning).
#include <cstdint>
#include <string>
#include <vector>

struct FT_LibraryRec_;
struct FT_FaceRec_;

namespace tessera::annotate {

/// Coverage 0..255 of a line of text, row 0 at the top; the baseline is row `ascent`.
struct TextMask {
  int width = 0, height = 0, ascent = 0;
  std::vector<std::uint8_t> coverage;  ///< width * height
};

class Font {
 public:
  /// Opens the face; throws std::runtime_error naming the file and FreeType's fault.
  explicit Font(const std::string& path);
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  /// Sets the em size in pixels (clamped to [1, 4096]).
  void set_pixel_size(int px);
  /// Ascender + descender of the face at this size, pixels.
  int line_height() const { return m_ascent + m_descent; }
  int ascent() const { return m_ascent; }

  /// The text rasterised, at most kMaxAnnotationGlyphs glyphs and at most `max_width` pixels
  /// wide (glyphs beyond either are left out). Bounded time: each glyph is rendered once.
  TextMask render(const std::string& utf8, int max_width) const;

 private:
  FT_LibraryRec_* m_library = nullptr;
  FT_FaceRec_* m_face = nullptr;
  std::string m_path;
  int m_ascent = 0, m_descent = 0;
};

/// UTF-8 to code points; each maximal subpart of an invalid or truncated sequence gives one
/// U+FFFD (next_utf8_char, message_text.h). At most `max_points` code points.
std::vector<char32_t> decode_utf8(const std::string& s, std::size_t max_points);

}  // namespace tessera::annotate
