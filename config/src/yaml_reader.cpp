#include "yaml_reader.h"

#include <tessera/message_text.h>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <algorithm>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <system_error>
#include <unordered_map>

namespace tessera::config::detail {
namespace {

std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

template <class T>
std::optional<T> parse_integer(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  T v{};
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

/// Records whether a document holds anything but an empty (null) root, and where it starts.
class ContentFinder final : public YAML::EventHandler {
 public:
  std::optional<SourceMark> first;
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { note(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { note(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    note(m);
  }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& m) {
    if (!first) first = SourceMark{m.line + 1, m.column + 1};
  }
};

/// A line that starts with a document marker: `---` or `...` then a blank or the end.
bool has_document_marker(const std::string& text) {
  for (std::size_t i = 0; i + 3 <= text.size();) {
    if (text.compare(i, 3, "---") == 0 || text.compare(i, 3, "...") == 0) {
      if (i + 3 == text.size() || std::string_view(" \t\r\n").find(text[i + 3]) != std::string_view::npos) return true;
    }
    const std::size_t nl = text.find('\n', i);
    if (nl == std::string::npos) break;
    i = nl + 1;
  }
  return false;
}

/// A number written with more characters than this is shown through format_number.
constexpr std::size_t kLongNumberText = 24;

/// `s` escaped and cut to `max` bytes (message_text.h), in quotes when `quoted`.
std::string shown_text(std::string_view s, bool quoted, std::size_t max = kMessageValueMax) {
  const std::string_view q = quoted ? "\"" : "";
  std::string out(q);
  if (s.size() <= max) return out.append(printable_text(s)).append(q);
  const std::string cut = shown_value(s, max);  // `aaa... (N characters)`
  const std::size_t dots = cut.rfind("... (");
  return out.append(cut, 0, dots).append(q).append(cut, dots);
}

}  // namespace

std::optional<SourceMark> second_document(const std::string& text) {
  if (!has_document_marker(text)) return std::nullopt;
  std::istringstream in(text);
  YAML::Parser parser(in);
  ContentFinder first, second;
  if (!parser.HandleNextDocument(first)) return std::nullopt;
  if (!parser.HandleNextDocument(second)) return std::nullopt;
  return second.first;
}

std::optional<ExplicitTag> first_explicit_tag(const YamlTree& tree) {
  const std::string& tag = tree.first_tag();
  if (tag.empty()) return std::nullopt;
  constexpr std::string_view kCore = "tag:yaml.org,2002:";
  std::string shown = tag;
  if (shown.rfind(kCore, 0) == 0) shown.replace(0, kCore.size(), "!!");
  std::string quoted(1, '\'');  // (appends: GCC 12 warns falsely (-Wrestrict) on "'" + ...)
  return ExplicitTag{tree.first_tag_mark(), quoted.append(cut_for_message(shown)).append(1, '\'')};
}

std::string cut_for_message(std::string_view s, std::size_t max) { return shown_text(s, false, max); }

bool Range::contains(double v) const {
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + (hi_open ? ")" : "]");
  }
  if (has_lo) return std::string(lo_open ? "(> " : "(>= ") + format_number(lo) + ")";
  if (has_hi) return std::string(hi_open ? "(< " : "(<= ") + format_number(hi) + ")";
  return "(any finite number)";
}

std::string join_words(const std::vector<std::string>& words, const char* last_sep, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) s += (i + 1 == words.size()) ? last_sep : sep;
    s += words[i];
  }
  return s;
}

std::string braced(std::span<const KeyShape> keys, bool names_only) {
  std::vector<std::string> entries;
  for (const KeyShape& k : keys)
    entries.push_back(names_only ? std::string(k.name) : std::string(k.name) + ": " + std::string(k.takes));
  std::string out(1, '{');  // (appends: GCC 12 warns falsely (-Wrestrict) on "{" + ...)
  return out.append(join_words(entries, ", ")).append(1, '}');
}

std::string mapping_with_keys(std::initializer_list<std::string_view> keys, std::string_view note) {
  std::string allowed = "a mapping with keys ";
  bool first = true;
  for (auto k : keys) {
    allowed.append(first ? "" : ", ").append(k);
    first = false;
  }
  return allowed.append(note);
}

// ---------------------------------------------------------------------------------------------
// Value

Value::Value(const Document* doc, SourceMark anchor) : Value(doc, doc->tree->root(), nullptr, {}, -1, anchor, false) {}

Value::Value(const Document* doc, YamlTree::Id id, Base base, std::string_view key, std::int64_t index,
             SourceMark anchor, bool anchor_is_key)
    : m_doc(doc),
      m_id(id),
      m_base(std::move(base)),
      m_key(key),
      m_index(index),
      m_anchor(anchor),
      m_anchor_is_key(anchor_is_key) {}

std::string Value::path() const {
  const std::string base = m_base ? *m_base : std::string();
  if (m_index >= 0) return base + "[" + std::to_string(m_index) + "]";
  if (!m_base) return base;
  const std::string shown = cut_for_message(m_key);  // a BOM or control character shows escaped
  return base.empty() ? shown : base + "." + shown;
}

SourceMark Value::mark() const {
  if (m_anchor_is_key) return m_anchor;
  const SourceMark m = m_doc->tree->mark(m_id);
  if (is_null() || m.line <= 0) return m_anchor;
  return m;
}

void Value::fail(const std::string& message) const { throw ConfigError(m_doc->file, mark(), path(), message); }

void Value::wrong_type(const std::string& allowed) const {
  fail(describe() + " is not allowed here (allowed: " + allowed + ")");
}

bool Value::is_word(std::string_view word) const { return is_scalar() && text() == word; }

std::string Value::describe() const {
  if (is_map()) return "a mapping";
  if (is_sequence()) return "a list";
  if (is_scalar()) {
    const std::string_view t = text();
    if (!plain()) return shown_text(t, true);
    // A long number reads short: `1e+299 (written with 300 characters)`
    if (t.size() > kLongNumberText) {
      if (const auto v = parse_double(t); v && std::isfinite(*v))
        return format_number(*v) + " (written with " + std::to_string(t.size()) + " characters)";
    }
    return cut_for_message(t);
  }
  return "an empty value";
}

double Value::number(const Range& r) const {
  const std::string allowed =
      std::isfinite(r.lo) || std::isfinite(r.hi) ? "a number in " + r.describe() : std::string("a finite number");
  if (!is_scalar() || !plain()) wrong_type(allowed);
  const auto v = parse_double(text());
  if (!v) fail(describe() + " is not a number (allowed: " + allowed + ")");
  if (!std::isfinite(*v)) fail(describe() + " is not finite (allowed: " + allowed + ")");
  if (!r.contains(*v)) fail(describe() + " is out of range " + r.describe());
  return *v;
}

std::int64_t Value::integer(std::int64_t lo, std::int64_t hi) const {
  std::string allowed = "an integer";
  const bool bounded_hi = hi < std::numeric_limits<std::int64_t>::max();
  const bool bounded_lo = lo > std::numeric_limits<std::int64_t>::min();
  std::string range;
  if (bounded_lo && bounded_hi) range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  else if (bounded_lo) range = "(>= " + std::to_string(lo) + ")";
  else if (bounded_hi) range = "(<= " + std::to_string(hi) + ")";
  if (!range.empty()) allowed += " in " + range;
  if (!is_scalar() || !plain()) wrong_type(allowed);
  const auto v = parse_integer<std::int64_t>(text());
  if (!v) {
    // Digits beyond 64 bits: out of range, not "not an integer"
    const auto d = parse_double(text());
    const bool digits_only = text().find_first_not_of("+-0123456789") == std::string_view::npos;
    if (d && digits_only && !range.empty()) fail(describe() + " is out of range " + range);
    fail(describe() + " is not an integer (allowed: " + allowed + ")");
  }
  if (*v < lo || *v > hi) fail(describe() + " is out of range " + range);
  return *v;
}

std::uint64_t Value::unsigned64() const {
  const std::string allowed = "an integer in [0, 18446744073709551615]";
  if (!is_scalar() || !plain()) wrong_type(allowed);
  const auto v = parse_integer<std::uint64_t>(text());
  if (!v) fail(describe() + " is not an unsigned 64-bit integer (allowed: " + allowed + ")");
  return *v;
}

bool Value::boolean() const {
  if (is_scalar() && plain()) {
    const std::string_view s = text();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail(describe() + " is not a boolean (allowed: true or false)");
  }
  wrong_type("true or false");
}

std::string Value::string(bool allow_empty) const {
  if (!is_scalar()) wrong_type("a string");
  if (!allow_empty && text().empty()) fail("empty string (allowed: a non-empty string)");
  // YAML is Unicode text: a byte that is not UTF-8 would be rewritten by the effective
  // config's writer (a different name or path on the way back), so it is refused here
  if (const std::size_t bad = first_invalid_utf8(text()); bad != std::string_view::npos) {
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(text()[bad])));
    fail(describe() + " is not valid UTF-8 (byte " + byte + " at offset " + std::to_string(bad) +
         "; allowed: UTF-8 text)");
  }
  return std::string(text());
}

std::string Value::drawn_text(bool allow_empty) const {
  if (!is_scalar()) wrong_type("a string");
  if (!allow_empty && text().empty()) fail("empty string (allowed: a non-empty string)");
  return with_replacement_characters(text());
}

Vec3 Value::triple(const char* shape, const Range& r) const {
  const ValueList xs = list(shape, 3, 3);
  return Vec3(xs[0].number(r), xs[1].number(r), xs[2].number(r));
}

Vec3 Value::vec3(const Range& r) const { return triple("[x, y, z]", r); }

Color Value::color(const Range& r) const { return triple("[r, g, b]", r); }

ValueList Value::list(const std::string& allowed, std::size_t min_size, std::size_t max_size) const {
  if (!is_sequence()) wrong_type(allowed);
  const std::size_t n = m_doc->tree->size(m_id);
  visit(n);
  if (n < min_size || n > max_size) {
    std::string count;
    if (min_size == max_size) count = "";
    else if (max_size == std::numeric_limits<std::size_t>::max())
      count = ", at least " + std::to_string(min_size) + " elements";
    else count = ", " + std::to_string(min_size) + " to " + std::to_string(max_size) + " elements";
    fail("list has " + std::to_string(n) + " element" + (n == 1 ? "" : "s") + " (allowed: " + allowed + count + ")");
  }
  return ValueList(*this);
}

Value Value::child(YamlTree::Id id, const Base& base, std::string_view key, SourceMark key_mark) const {
  return Value(m_doc, id, base, key, -1, key_mark, true);
}

Value Value::element(YamlTree::Id id, const Base& base, std::size_t index) const {
  return Value(m_doc, id, base, {}, static_cast<std::int64_t>(index), mark(), false);
}

void Value::visit(std::size_t n) const {
  m_doc->nodes_visited += n;
  if (m_doc->nodes_visited > m_doc->node_budget) {
    fail("the config expands to more than " + std::to_string(m_doc->node_budget) +
         " nodes (aliases counted each time they are used; allowed: at most 1000000, or half "
         "the file size in bytes when that is more)");
  }
}

Map Value::map(const std::string& allowed) const {
  if (!is_map()) wrong_type(allowed);
  const YamlTree& t = *m_doc->tree;
  const std::size_t n = t.size(m_id);
  // Keys are plain words, each once: sorted by key (then by position), a repeated key is
  // next to its first; the one reported is the earliest second occurrence, as a reader meets it
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) {
    visit(1);
    const YamlTree::Id k = t.key(m_id, i);
    if (t.kind(k) != YamlTree::Kind::Scalar)
      throw ConfigError(m_doc->file, t.mark(k), path(), "a key must be a plain word");
    order[i] = static_cast<std::uint32_t>(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return t.scalar(t.key(m_id, a)) < t.scalar(t.key(m_id, b));
  });
  std::size_t first = n, second = n;
  for (std::size_t j = 1, group = 0; j < n; ++j) {
    if (t.scalar(t.key(m_id, order[j])) != t.scalar(t.key(m_id, order[j - 1]))) {
      group = j;
    } else if (j == group + 1 && order[j] < second) {
      first = order[group];
      second = order[j];
    }
  }
  const Map m(*this);
  if (second < n) {
    throw ConfigError(m_doc->file, t.mark(t.key(m_id, second)), m.entry(first).path(),
                      "duplicate key (first given at line " + std::to_string(t.mark(t.key(m_id, first)).line) + ")");
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// ValueList

ValueList::ValueList(const Value& list)
    : m_list(list),
      m_base(std::make_shared<const std::string>(list.path())),
      m_size(list.m_doc->tree->size(list.m_id)) {}

Value ValueList::operator[](std::size_t i) const {
  return m_list.element(m_list.m_doc->tree->element(m_list.m_id, i), m_base, i);
}

}  // namespace tessera::config::detail
