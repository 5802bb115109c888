// Text from outside the program made safe to echo in messages (contract in message_text.h).
#include <tessera/message_text.h>

#include <cstdint>
#include <cstdio>

namespace tessera {
namespace {

/// The length of the valid UTF-8 character at s[i] and its code point; 0 if the byte there
/// does not start one (a stray continuation byte, an overlong form, a surrogate, > U+10FFFF,
/// a sequence cut short).
std::size_t utf8_char(std::string_view s, std::size_t i, char32_t& cp) {
  const Utf8Char c = next_utf8_char(s, i);
  if (!c.valid) return 0;
  cp = c.code_point;
  return c.length;
}

/// Characters that print as nothing (or move the text around) on a terminal.
bool invisible(char32_t cp) {
  return (cp >= 0x80 && cp <= 0x9F) || cp == 0xAD || cp == 0x34F || cp == 0x61C || cp == 0x180E ||
         (cp >= 0x200B && cp <= 0x200F) || (cp >= 0x2028 && cp <= 0x202E) || (cp >= 0x2060 && cp <= 0x206F) ||
         cp == 0xFEFF || (cp >= 0xFFF9 && cp <= 0xFFFB) || cp == 0xFFFE || cp == 0xFFFF ||
         (cp >= 0xE0000 && cp <= 0xE007F);
}

void append_byte_escape(std::string& out, unsigned char b) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "\\x%02x", b);
  out += buf;
}

/// Where to cut `s` at most `at` bytes in without splitting a UTF-8 character.
std::size_t cut_before(std::string_view s, std::size_t at) {
  if (at >= s.size()) return s.size();
  std::size_t k = at;
  for (int back = 0; back < 3 && k > 0 && (static_cast<unsigned char>(s[k]) & 0xC0) == 0x80; ++back) --k;
  return (static_cast<unsigned char>(s[k]) & 0xC0) == 0x80 ? at : k;
}

/// Where to start the last at most `n` bytes of `s` without splitting a UTF-8 character.
std::size_t cut_after(std::string_view s, std::size_t n) {
  if (n >= s.size()) return 0;
  std::size_t k = s.size() - n;
  for (int fwd = 0; fwd < 3 && k < s.size() && (static_cast<unsigned char>(s[k]) & 0xC0) == 0x80; ++fwd) ++k;
  return k;
}

}  // namespace

Utf8Char next_utf8_char(std::string_view s, std::size_t i) {
  const auto b0 = static_cast<unsigned char>(s[i]);
  if (b0 < 0x80) return {1, b0, true};
  // Well-formed sequences (Unicode table 3-7): the lead byte fixes the length and the range
  // of the second byte (no overlong forms, surrogates or code points past U+10FFFF)
  std::size_t n = 0;
  char32_t cp = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
    cp = b0 & 0x1F;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    cp = b0 & 0x0F;
    if (b0 == 0xE0) lo = 0xA0;
    if (b0 == 0xED) hi = 0x9F;
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    cp = b0 & 0x07;
    if (b0 == 0xF0) lo = 0x90;
    if (b0 == 0xF4) hi = 0x8F;
  } else {
    return {1, 0xFFFD, false};
  }
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = i + k < s.size() ? static_cast<unsigned char>(s[i + k]) : 0;
    if (i + k >= s.size() || b < lo || b > hi) return {k, 0xFFFD, false};  // the maximal subpart
    cp = (cp << 6) | (b & 0x3F);
    lo = 0x80;
    hi = 0xBF;
  }
  return {n, cp, true};
}

std::string with_replacement_characters(std::string_view s) {
  if (first_invalid_utf8(s) == std::string_view::npos) return std::string(s);
  std::string out;
  out.reserve(s.size() + s.size() / 2);
  for (std::size_t i = 0; i < s.size();) {
    const Utf8Char c = next_utf8_char(s, i);
    if (c.valid) out.append(s.substr(i, c.length));
    else out += "\xEF\xBF\xBD";
    i += c.length;
  }
  return out;
}

std::size_t first_invalid_utf8(std::string_view s) {
  char32_t cp = 0;
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_char(s, i, cp);
    if (n == 0) return i;
    i += n;
  }
  return std::string_view::npos;
}

std::string printable_text(std::string_view s, bool keep_newlines) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    char32_t cp = 0;
    const std::size_t n = utf8_char(s, i, cp);
    if (n == 0) {  // not UTF-8: the byte itself
      append_byte_escape(out, static_cast<unsigned char>(s[i]));
      ++i;
      continue;
    }
    if (cp < 0x20 || cp == 0x7F) {
      if (cp == '\n' && keep_newlines) out += '\n';
      else append_byte_escape(out, static_cast<unsigned char>(cp));
    } else if (invisible(cp)) {
      char buf[16];
      std::snprintf(buf, sizeof buf, "\\u{%04X}", static_cast<unsigned>(cp));
      out += buf;
    } else {
      out.append(s.substr(i, n));
    }
    i += n;
  }
  return out;
}

std::string shown_value(std::string_view s, std::size_t max) {
  if (s.size() <= max) return printable_text(s);
  return printable_text(s.substr(0, cut_before(s, max))) + "... (" + std::to_string(s.size()) + " characters)";
}

std::string shown_path(std::string_view s, std::size_t max) {
  if (s.size() <= max) return printable_text(s);
  const std::size_t head = cut_before(s, max / 2);
  const std::size_t tail = cut_after(s, max / 2);
  return printable_text(s.substr(0, head)) + "..." + printable_text(s.substr(tail)) + " (" + std::to_string(s.size()) +
         " characters)";
}

std::string message_quoting(std::string message, std::string_view path) {
  // Pieces: copies of a long `path` (shown short), and the text around them
  std::string out;
  const auto plain = [&](std::string_view text) {
    // A run of more than kShownPathMax bytes without a blank (a path built from `path`, a
    // long file name) is cut like a path too
    std::size_t i = 0;
    while (i < text.size()) {
      const std::size_t blank = text.find_first_of(" \n", i);
      const std::size_t end = blank == std::string_view::npos ? text.size() : blank;
      const std::string_view word = text.substr(i, end - i);
      out += word.size() > kShownPathMax ? shown_path(word) : printable_text(word);
      if (end < text.size()) out += text[end];
      i = end + 1;
    }
  };
  std::size_t from = 0;
  if (path.size() > kShownPathMax) {
    const std::string shown = shown_path(path);
    for (std::size_t at; (at = message.find(path, from)) != std::string::npos; from = at + path.size()) {
      plain(std::string_view(message).substr(from, at - from));
      out += shown;
    }
  }
  plain(std::string_view(message).substr(from));
  return out;
}

}  // namespace tessera
