#pragma once
/// Text from outside the program (a path, a name, a YAML value, an environment variable, file
/// contents) as it may appear in a message: on one line, every character visible, and short.
///
/// Escapes: ASCII control characters (tab and newline included) and bytes that are not valid
/// UTF-8 as `\xHH` (one per byte); other invisible characters (C1 controls, a byte order mark,
/// zero-width spaces and joiners, bidirectional controls, soft hyphen, line and paragraph
/// separators, tag characters, U+FFFE/U+FFFF) as `\u{HHHH}`, e.g. a BOM reads `\u{FEFF}`. Everything else, other scripts included, is kept as written.
/// Lengths count bytes of the original text. Cuts never split a UTF-8 character.
/// Thread-safe (pure functions).
#include <cstddef>
#include <string>
#include <string_view>

namespace tessera {

/// Values (names, YAML scalars) are cut to this many bytes.
inline constexpr std::size_t kShownValueMax = 64;
/// Paths are cut to about this many bytes: their first and last parts.
inline constexpr std::size_t kShownPathMax = 200;

/// The byte offset of the first byte of `s` that does not start a valid UTF-8 character (a
/// stray continuation byte, an overlong form, a surrogate, a code point past U+10FFFF, a
/// sequence cut short), or std::string_view::npos when all of `s` is valid UTF-8.
std::size_t first_invalid_utf8(std::string_view s);

/// One step of decoding UTF-8: the character at a byte offset, or where the bytes there are
/// not UTF-8, U+FFFD standing for the maximal subpart of the ill-formed sequence (Unicode's
/// recommended practice, chapter 3, "U+FFFD Substitution of Maximal Subparts": the bytes
/// that begin a well-formed sequence but do not complete it, else the one byte).
struct Utf8Char {
  std::size_t length = 1;   ///< bytes taken, at least 1
  char32_t code_point = 0;  ///< U+FFFD where !valid
  bool valid = true;
};

/// The character at s[i] (i < s.size()).
Utf8Char next_utf8_char(std::string_view s, std::size_t i);

/// `s` with each maximal subpart of an ill-formed UTF-8 sequence replaced by U+FFFD (bytes EF BF
/// BD): "\xE2\x82" (cut short) is one, "\xC0\xAF" (never UTF-8) two, a surrogate's three
/// bytes three. Valid UTF-8 is returned unchanged, and the result is always valid UTF-8.
std::string with_replacement_characters(std::string_view s);

/// `s` with the escapes above, not cut. A newline is kept only when `keep_newlines`.
std::string printable_text(std::string_view s, bool keep_newlines = false);

/// `s` escaped, and when longer than `max` bytes cut to its first `max`:
/// `aaaa... (10485760 characters)`.
std::string shown_value(std::string_view s, std::size_t max = kShownValueMax);

/// `s` escaped, and when longer than `max` bytes cut to its first and last `max / 2`, so the
/// directory it starts in and the file name both stay visible:
/// `/scratch/aaaa...aaaa/image.png (5012 characters)`.
std::string shown_path(std::string_view s, std::size_t max = kShownPathMax);

/// A whole message (which may quote `path` once or more, e.g. a std::filesystem error) with
/// every copy of a `path` longer than kShownPathMax replaced by shown_path(path), every other
/// run of more than kShownPathMax bytes without a blank (a path built on `path`, a long file
/// name) replaced by its shown_path, and the rest made printable (newlines kept).
std::string message_quoting(std::string message, std::string_view path);

}  // namespace tessera
