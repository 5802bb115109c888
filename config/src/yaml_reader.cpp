#include "yaml_reader.h"

#include <tessera/message_text.h>

#include <yaml-cpp/eventhandler.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <system_error>
#include <unordered_map>

namespace tessera::config::detail {
namespace {

/// A plain (unquoted) scalar: the only kind that may be a number or a boolean.
bool is_plain(const YAML::Node& n) { return n.IsScalar() && n.Tag() == "?"; }

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
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                const std::string&) override { note(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override { note(m); }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override { note(m); }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& m) {
    if (!first) first = SourceMark{m.line + 1, m.column + 1};
  }
};

/// Records the first node that carries an explicit tag.
class TagFinder final : public YAML::EventHandler {
 public:
  std::optional<ExplicitTag> found;
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark& m, const std::string& tag, YAML::anchor_t,
                const std::string&) override { note(m, tag); }
  void OnSequenceStart(const YAML::Mark& m, const std::string& tag, YAML::anchor_t,
                       YAML::EmitterStyle::value) override { note(m, tag); }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string& tag, YAML::anchor_t,
                  YAML::EmitterStyle::value) override { note(m, tag); }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& m, const std::string& tag) {
    if (found || tag.empty() || tag == "?" || tag == "!") return;
    constexpr std::string_view kCore = "tag:yaml.org,2002:";
    const std::string shown = tag.rfind(kCore, 0) == 0 ? "!!" + tag.substr(kCore.size()) : tag;
    found = ExplicitTag{SourceMark{m.line + 1, m.column + 1}, "'" + cut_for_message(shown) + "'"};
  }
};

/// A line that starts with a document marker: `---` or `...` then a blank or the end.
bool has_document_marker(const std::string& text) {
  for (std::size_t i = 0; i + 3 <= text.size();) {
    if (text.compare(i, 3, "---") == 0 || text.compare(i, 3, "...") == 0) {
      if (i + 3 == text.size() || std::string_view(" \t\r\n").find(text[i + 3]) != std::string_view::npos)
        return true;
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

std::optional<ExplicitTag> first_explicit_tag(const std::string& text) {
  if (text.find('!') == std::string::npos) return std::nullopt;
  std::istringstream in(text);
  YAML::Parser parser(in);
  TagFinder finder;
  parser.HandleNextDocument(finder);
  return finder.found;
}

std::string cut_for_message(std::string_view s, std::size_t max) {
  return shown_text(s, false, max);
}

bool Range::contains(double v) const {
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return std::string(lo_open ? "(> " : "(>= ") + format_number(lo) + ")";
  if (has_hi) return std::string(hi_open ? "(< " : "(<= ") + format_number(hi) + ")";
  return "(any finite number)";
}

std::string format_number(double v) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, ec == std::errc() ? end : buf);
}

std::string join_words(const std::vector<std::string>& words, const char* last_sep, const char* sep) {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) s += (i + 1 == words.size()) ? last_sep : sep;
    s += words[i];
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// Value

Value::Value(YAML::Node node, std::string path, const Document* doc, SourceMark anchor,
             bool anchor_is_key)
    : m_node(std::move(node)),
      m_path(std::move(path)),
      m_doc(doc),
      m_anchor(anchor),
      m_anchor_is_key(anchor_is_key) {}

SourceMark Value::mark() const {
  if (m_anchor_is_key) return m_anchor;
  const YAML::Mark m = m_node.Mark();
  if (m_node.IsNull() || m.is_null() || m.line < 0) return m_anchor;
  return SourceMark{m.line + 1, m.column + 1};
}

void Value::fail(const std::string& message) const {
  throw ConfigError(m_doc->file, mark(), m_path, message);
}

void Value::wrong_type(const std::string& allowed) const {
  fail(describe() + " is not allowed here (allowed: " + allowed + ")");
}

bool Value::is_word(std::string_view word) const {
  return m_node.IsScalar() && m_node.Scalar() == word;
}

std::string Value::describe() const {
  if (m_node.IsMap()) return "a mapping";
  if (m_node.IsSequence()) return "a list";
  if (m_node.IsScalar()) {
    const std::string& text = m_node.Scalar();
    if (!is_plain(m_node)) return shown_text(text, true);
    // A long number reads short: `1e+299 (written with 300 characters)`
    if (text.size() > kLongNumberText) {
      if (const auto v = parse_double(text); v && std::isfinite(*v))
        return format_number(*v) + " (written with " + std::to_string(text.size()) + " characters)";
    }
    return cut_for_message(text);
  }
  return "an empty value";
}

double Value::number(const Range& r) const {
  const std::string allowed = std::isfinite(r.lo) || std::isfinite(r.hi)
                                  ? "a number in " + r.describe()
                                  : std::string("a finite number");
  if (!is_plain(m_node)) wrong_type(allowed);
  const auto v = parse_double(m_node.Scalar());
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
  if (!is_plain(m_node)) wrong_type(allowed);
  const auto v = parse_integer<std::int64_t>(m_node.Scalar());
  if (!v) {
    // Digits beyond 64 bits: out of range, not "not an integer"
    const auto d = parse_double(m_node.Scalar());
    const bool digits_only = m_node.Scalar().find_first_not_of("+-0123456789") == std::string::npos;
    if (d && digits_only && !range.empty()) fail(describe() + " is out of range " + range);
    fail(describe() + " is not an integer (allowed: " + allowed + ")");
  }
  if (*v < lo || *v > hi) fail(describe() + " is out of range " + range);
  return *v;
}

std::uint64_t Value::unsigned64() const {
  const std::string allowed = "an integer in [0, 18446744073709551615]";
  if (!is_plain(m_node)) wrong_type(allowed);
  const auto v = parse_integer<std::uint64_t>(m_node.Scalar());
  if (!v) fail(describe() + " is not an unsigned 64-bit integer (allowed: " + allowed + ")");
  return *v;
}

bool Value::boolean() const {
  if (is_plain(m_node)) {
    const std::string& s = m_node.Scalar();
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail(describe() + " is not a boolean (allowed: true or false)");
  }
  wrong_type("true or false");
}

std::string Value::string(bool allow_empty) const {
  if (!m_node.IsScalar()) wrong_type("a string");
  if (!allow_empty && m_node.Scalar().empty()) fail("empty string (allowed: a non-empty string)");
  return m_node.Scalar();
}

Vec3 Value::triple(const char* shape, const Range& r) const {
  const auto xs = list(shape, 3, 3);
  return Vec3(xs[0].number(r), xs[1].number(r), xs[2].number(r));
}

Vec3 Value::vec3(const Range& r) const { return triple("[x, y, z]", r); }

Color Value::color(const Range& r) const { return triple("[r, g, b]", r); }

std::vector<Value> Value::list(const std::string& allowed, std::size_t min_size,
                               std::size_t max_size) const {
  if (!m_node.IsSequence()) wrong_type(allowed);
  const std::size_t n = m_node.size();
  visit(n);
  if (n < min_size || n > max_size) {
    std::string count;
    if (min_size == max_size) count = "";
    else if (max_size == std::numeric_limits<std::size_t>::max())
      count = ", at least " + std::to_string(min_size) + " elements";
    else count = ", " + std::to_string(min_size) + " to " + std::to_string(max_size) + " elements";
    fail("list has " + std::to_string(n) + " element" + (n == 1 ? "" : "s") + " (allowed: " +
         allowed + count + ")");
  }
  std::vector<Value> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(element(m_node[i], i));
  return out;
}

Value Value::child(const YAML::Node& n, const std::string& key, SourceMark key_mark) const {
  const std::string shown = cut_for_message(key);  // a BOM or control character shows escaped
  return Value(n, m_path.empty() ? shown : m_path + "." + shown, m_doc, key_mark, true);
}

void Value::visit(std::size_t n) const {
  m_doc->nodes_visited += n;
  if (m_doc->nodes_visited > m_doc->node_budget) {
    fail("the config expands to more than " + std::to_string(m_doc->node_budget) +
         " nodes (aliases counted each time they are used; allowed: at most 1000000, or half "
         "the file size in bytes when that is more)");
  }
}

Value Value::element(const YAML::Node& n, std::size_t index) const {
  return Value(n, m_path + "[" + std::to_string(index) + "]", m_doc, mark(), false);
}

Map Value::map(const std::string& allowed) const {
  if (!m_node.IsMap()) wrong_type(allowed);
  std::vector<std::pair<std::string, Value>> entries;
  std::vector<SourceMark> key_marks;
  std::unordered_map<std::string, std::size_t> index;  // key -> entry, for duplicates
  for (const auto& kv : m_node) {  // kv: a pair of node handles, held by value
    visit(1);
    const YAML::Node k = kv.first;
    const YAML::Mark km = k.Mark();
    const SourceMark key_mark{km.line + 1, km.column + 1};
    if (!k.IsScalar()) {
      throw ConfigError(m_doc->file, key_mark, m_path, "a key must be a plain word");
    }
    const std::string& key = k.Scalar();
    const auto [it, fresh] = index.emplace(key, entries.size());
    if (!fresh) {
      const SourceMark first = key_marks[it->second];
      throw ConfigError(m_doc->file, key_mark, entries[it->second].second.path(),
                        "duplicate key (first given at line " + std::to_string(first.line) + ")");
    }
    entries.emplace_back(key, child(kv.second, key, key_mark));
    key_marks.push_back(key_mark);
  }
  return Map(*this, std::move(entries), std::move(key_marks));
}

// ---------------------------------------------------------------------------------------------
// Map

Map::Map(Value self, std::vector<std::pair<std::string, Value>> entries,
         std::vector<SourceMark> key_marks)
    : m_self(std::move(self)), m_entries(std::move(entries)), m_key_marks(std::move(key_marks)) {}

void Map::allow(std::initializer_list<std::string_view> keys) const {
  for (std::size_t i = 0; i < m_entries.size(); ++i) {
    bool known = false;
    for (auto k : keys) known = known || k == m_entries[i].first;
    if (known) continue;
    std::string list;
    for (auto k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
    throw ConfigError(m_self.doc().file, m_key_marks[i], m_entries[i].second.path(),
                      "unknown key (allowed: " + list + ")");
  }
}

bool Map::has(std::string_view key) const {
  for (const auto& e : m_entries)
    if (e.first == key) return true;
  return false;
}

std::optional<Value> Map::get(std::string_view key) const {
  for (const auto& e : m_entries)
    if (e.first == key) return e.second;
  return std::nullopt;
}

Value Map::require(std::string_view key, const std::string& what) const {
  if (auto v = get(key)) return *v;
  const std::string path =
      m_self.path().empty() ? std::string(key) : m_self.path() + "." + std::string(key);
  throw ConfigError(m_self.doc().file, m_self.mark(), path,
                    "missing required key (allowed: " + what + ")");
}

double Map::number_or(std::string_view key, double fallback, const Range& r) const {
  const auto v = get(key);
  return v ? v->number(r) : fallback;
}

std::int64_t Map::integer_or(std::string_view key, std::int64_t fallback, std::int64_t lo,
                             std::int64_t hi) const {
  const auto v = get(key);
  return v ? v->integer(lo, hi) : fallback;
}

bool Map::boolean_or(std::string_view key, bool fallback) const {
  const auto v = get(key);
  return v ? v->boolean() : fallback;
}

Vec3 Map::vec3_or(std::string_view key, const Vec3& fallback, const Range& r) const {
  const auto v = get(key);
  return v ? v->vec3(r) : fallback;
}

Color Map::color_or(std::string_view key, const Color& fallback, const Range& r) const {
  const auto v = get(key);
  return v ? v->color(r) : fallback;
}

}  // namespace tessera::config::detail
