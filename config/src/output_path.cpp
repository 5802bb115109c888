// Output file name patterns: {name} {step} {time} {rank} with fmt-like specs.
#include <tessera/config/annotations.h>
#include <tessera/config/output_path.h>

#include "yaml_reader.h"

#include <charconv>
#include <cstdio>
#include <stdexcept>
#include <string_view>

namespace tessera::config {
namespace {

enum class Field { Name, Step, Time, Rank };

/// `[0][width][.precision][type]`, parsed and checked against the field's kind.
struct Spec {
  bool zero = false;
  int width = 0;
  int precision = -1;
  char type = 0;
};

/// Output file names, or annotation text (no file-name rules, no {rank}).
enum class Use { File, Text };

constexpr std::string_view kFilePrefix = "bad output pattern", kTextPrefix = "bad text pattern";

[[noreturn]] void bad(const std::string& pattern, const std::string& what) {
  throw std::invalid_argument(std::string(kFilePrefix) + " \"" + detail::cut_for_message(pattern) + "\": " + what);
}

/// Runs f(); a fault it reports is reported as one of a text pattern.
template <class F>
void as_text(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    const std::string_view m = e.what();
    if (m.substr(0, kFilePrefix.size()) != kFilePrefix) throw;
    throw std::invalid_argument(std::string(kTextPrefix) + std::string(m.substr(kFilePrefix.size())));
  }
}

Spec parse_spec(const std::string& pattern, std::string_view placeholder, Field field, std::string_view s, Use use) {
  Spec spec;
  std::size_t i = 0;
  const auto digits = [&](int& out) {
    const std::size_t start = i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
    if (i == start) return false;
    if (i - start > 3) bad(pattern, "width or precision too large in {" + std::string(placeholder) + "}");
    std::from_chars(s.data() + start, s.data() + i, out);
    return true;
  };
  if (i < s.size() && s[i] == '0') {
    spec.zero = true;
    ++i;
  }
  digits(spec.width);
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (!digits(spec.precision)) bad(pattern, "missing precision after '.' in {" + std::string(placeholder) + "}");
  }
  if (i < s.size()) spec.type = s[i++];
  if (i != s.size()) {
    bad(pattern, "unsupported format spec in {" + std::string(placeholder) +
                     "} (allowed: [0][width][.precision][type], e.g. {step:06d}, {time:.3f})");
  }
  // Which parts each field accepts
  switch (field) {
    case Field::Step:
    case Field::Rank:
      if (spec.precision >= 0 || (spec.type != 0 && spec.type != 'd'))
        bad(pattern, "{" + std::string(placeholder) + "} is an integer (allowed: [0][width][d], e.g. {step:06d})");
      break;
    case Field::Time:
      if (spec.type != 0 && spec.type != 'f' && spec.type != 'e' && spec.type != 'g')
        bad(pattern,
            "{" + std::string(placeholder) + "} is a number (allowed: [0][width][.precision][f|e|g], e.g. {time:.3f})");
      break;
    case Field::Name:
      if (spec.zero || spec.precision >= 0 || (spec.type != 0 && spec.type != 's'))
        bad(pattern, "{" + std::string(placeholder) + "} is a string (allowed: [width][s])");
      break;
  }
  return spec;
}

std::string pad(std::string s, const Spec& spec, bool left_align) {
  if (static_cast<int>(s.size()) >= spec.width) return s;
  const std::size_t n = spec.width - s.size();
  if (left_align) return s + std::string(n, ' ');
  if (spec.zero) {
    const std::size_t sign = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
    return s.insert(sign, n, '0');
  }
  return std::string(n, ' ') + s;
}

std::string format_time(double t, const Spec& spec) {
  if (spec.type == 0 && spec.precision < 0) return format_number(t);
  char buf[512];
  const char type = spec.type == 0 ? 'g' : spec.type;
  const int precision = spec.precision < 0 ? 6 : spec.precision;
  const char fmt[] = {'%', '.', '*', type, '\0'};
  std::snprintf(buf, sizeof buf, fmt, precision, t);
  return buf;
}

/// Walks the pattern; with `out` set, writes the result there.
void expand(const std::string& pattern, const std::string& name, std::int64_t step, double time, int rank,
            std::string* out, Use use = Use::File) {
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (c == '}') {
      if (i + 1 < pattern.size() && pattern[i + 1] == '}') {
        if (out) *out += '}';
        ++i;
        continue;
      }
      bad(pattern, "unmatched '}' at position " + std::to_string(i + 1) + " (write }} for a literal brace)");
    }
    if (c != '{') {
      if (out) *out += c;
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '{') {
      if (out) *out += '{';
      ++i;
      continue;
    }
    // A placeholder: {key} or {key:spec}
    const std::size_t close = pattern.find('}', i);
    if (close == std::string::npos) bad(pattern, "unclosed '{' at position " + std::to_string(i + 1));
    const std::string_view inner(pattern.data() + i + 1, close - i - 1);
    const std::size_t colon = inner.find(':');
    const std::string_view key = inner.substr(0, colon);
    const std::string_view spec_text = colon == std::string_view::npos ? std::string_view() : inner.substr(colon + 1);
    Field field;
    if (key == "name") field = Field::Name;
    else if (key == "step") field = Field::Step;
    else if (key == "time") field = Field::Time;
    else if (key == "rank" && use == Use::File) field = Field::Rank;
    else
      bad(pattern, "unknown placeholder {" + detail::cut_for_message(key) + "} (allowed: {name} {step} {time}" +
                       (use == Use::File ? " {rank})" : ")"));
    const Spec spec = parse_spec(pattern, inner, field, spec_text, use);
    if (out) {
      switch (field) {
        case Field::Name: *out += pad(name, spec, true); break;
        case Field::Step: *out += pad(std::to_string(step), spec, false); break;
        case Field::Rank: *out += pad(std::to_string(rank), spec, false); break;
        case Field::Time: *out += pad(format_time(time, spec), spec, false); break;
      }
    }
    i = close;
  }
}

/// The name (the pattern as written, or expanded) must stay a file inside output_dir:
/// relative, no `.` or `..` component, and a final name neither empty nor hidden (a leading
/// '.'). A fault of the pattern as written stays one after expansion, so checking it first
/// names it without the expansion.
void require_inside(const std::string& pattern, const std::string& name) {
  const auto fault = [&](const std::string& what, const std::string& allowed) {
    bad(pattern, what + (name == pattern ? "" : " after formatting (gives \"" + detail::cut_for_message(name) + "\")") +
                     " (allowed: " + allowed + ")");
  };
  if (!name.empty() && name.front() == '/')
    fault("is an absolute path, which would write outside output_dir",
          "a name relative to output_dir, e.g. \"images/{name}\"; set output_dir to write elsewhere");
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = name.find('/', start);
    const std::string_view part(name.data() + start, (slash == std::string::npos ? name.size() : slash) - start);
    if (part == "..")
      fault("has a '..' component, which would write outside output_dir",
            "names below output_dir, e.g. \"images/{name}\"; set output_dir to write elsewhere");
    if (part == ".") fault("has a '.' component", "directory and file names, e.g. \"images/{name}\"");
    if (slash == std::string::npos) {
      if (part.empty()) fault("gives an empty file name", "a file name, e.g. \"{name}\"");
      if (part.front() == '.')
        fault("gives a hidden file name (starting with '.')",
              "a file name that does not start with '.', e.g. \"{name}\"");
      break;
    }
    start = slash + 1;
  }
}

/// Text patterns: printable, one line, known placeholders (faults as output patterns').
void check_text_pattern(const std::string& pattern) {
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const auto c = static_cast<unsigned char>(pattern[i]);
    if (c < 0x20 || c == 0x7f) {
      bad(pattern, "control character " + detail::cut_for_message(std::string(1, pattern[i])) + " at position " +
                       std::to_string(i + 1) + " (allowed: printable characters, one line)");
    }
  }
  expand(pattern, {}, 0, 0.0, 0, nullptr, Use::Text);
}

}  // namespace

void validate_output_pattern(const std::string& pattern) {
  if (pattern.empty()) throw std::invalid_argument("empty output pattern (allowed: e.g. \"{name}_{step:06d}\")");
  // A NUL would cut the name short (every format then writes the same file); other control
  // characters make names no one can type
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const auto c = static_cast<unsigned char>(pattern[i]);
    if (c < 0x20 || c == 0x7f) {
      bad(pattern, "control character " + detail::cut_for_message(std::string(1, pattern[i])) + " at position " +
                       std::to_string(i + 1) + " (allowed: printable characters)");
    }
  }
  if (pattern.back() == '/') {
    bad(pattern, "ends with '/' so the file name is empty (allowed: a file name, e.g. "
                 "\"images/{name}\")");
  }
  expand(pattern, {}, 0, 0.0, 0, nullptr);
  // Where it writes: as written, then with a stand-in name ({name} is a word of letters,
  // digits, _ and -)
  require_inside(pattern, pattern);
  std::string sample;
  expand(pattern, "x", 0, 0.0, 0, &sample);
  require_inside(pattern, sample);
}

std::string format_output_path(const std::string& pattern, const std::string& name, std::int64_t step, double time,
                               int rank) {
  validate_output_pattern(pattern);
  std::string out;
  expand(pattern, name, step, time, rank, &out);
  require_inside(pattern, out);  // the real name, step and time, checked again
  return out;
}

void validate_text_pattern(const std::string& pattern) {
  as_text([&] { check_text_pattern(pattern); });
}

std::string format_text_pattern(const std::string& pattern, const std::string& name, std::int64_t step, double time) {
  std::string out;
  as_text([&] {
    check_text_pattern(pattern);
    expand(pattern, name, step, time, 0, &out, Use::Text);
  });
  return out;
}

}  // namespace tessera::config
