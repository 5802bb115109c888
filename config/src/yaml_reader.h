#pragma once
// Private: typed, validating access to a parsed YAML document (yaml_tree.h). Every accessor
// either returns a value that satisfies the stated constraint or throws ConfigError at the
// node's file:line:col with its key path and what is allowed.
#include <tessera/config/config_error.h>
#include <tessera/math.h>
#include <tessera/number_text.h>  // format_number: shortest text that reads back as the same double

#include "yaml_tree.h"

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tessera::config::detail {

/// Bounds on what loading a config may cost (docs/config.md "Limits"):
/// - a config file is at most kMaxConfigBytes (checked before reading it; yaml-cpp parses
///   a few MB per second, so this also bounds the parse to about a second);
/// - the walk over the tree visits at most node_budget(text size) list elements and mapping
///   entries, an alias counted each time it is walked: max(kNodeBudgetBase, size / 2). A
///   file without aliases needs at least two bytes per node ("1," in a flow list, "-\n" in a
///   block list), so only alias expansion can reach the budget;
/// - the tree holds at most kMaxYamlNodes nodes (list elements, keys, values, aliases),
///   counted while it is built (YamlTree::parse), so the parse's memory stays bounded
///   (about 64 MiB for the tree at the bound). A key without a value (`{a, b}`) makes two
///   nodes from two bytes, so a 4 MiB file can reach it; other files cannot.
inline constexpr std::size_t kMaxConfigBytes = std::size_t(4) << 20;  // 4 MiB
inline constexpr std::size_t kNodeBudgetBase = 1'000'000;
inline constexpr std::size_t kMaxYamlNodes = std::size_t(1) << 21;  // 2,097,152
inline constexpr std::size_t node_budget(std::size_t text_bytes) {
  return text_bytes / 2 > kNodeBudgetBase ? text_bytes / 2 : kNodeBudgetBase;
}

/// The file being parsed: what messages call it, what relative names resolve against, its
/// tree, and how many nodes the walk has visited (the alias-expansion budget above).
struct Document {
  std::string file;
  std::string base_dir;
  const YamlTree* tree = nullptr;  ///< outlives every Value of the document
  std::size_t node_budget = kNodeBudgetBase;
  mutable std::size_t nodes_visited = 0;
};

/// Where a second, non-empty YAML document starts in `text`, if there is one. Cheap when the
/// text has no document marker (a line starting with `---` or `...`); otherwise the text is
/// scanned once more by yaml-cpp's event parser, for two documents at most (yaml-cpp's own
/// LoadAll can loop without end on malformed input). Throws YAML::Exception on bad syntax.
std::optional<SourceMark> second_document(const std::string& text);

/// An explicit tag in the text (`!foo`, `!!binary`, `!<tag:x>`), shown as written where
/// yaml-cpp allows (`!!binary` for tag:yaml.org,2002:binary) and escaped, and where its node
/// starts.
struct ExplicitTag {
  SourceMark mark;
  std::string tag;
};
/// The tree's first explicit tag (YamlTree::first_tag), shown for a message, or nothing.
std::optional<ExplicitTag> first_explicit_tag(const YamlTree& tree);

/// Values echoed in messages are cut to this many characters, then "..." and the full length:
/// `"aaaa..." (10485760 characters)`.
inline constexpr std::size_t kMessageValueMax = 64;
/// `s` as it may appear in a message: itself when short, else its first `max` characters,
/// "..." and " (N characters)"; control characters, invalid UTF-8 and invisible characters
/// such as a BOM are escaped (tessera::shown_value). Paths use tessera::shown_path instead.
std::string cut_for_message(std::string_view s, std::size_t max = kMessageValueMax);

/// An interval of allowed numbers, with its description for messages.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static Range any() { return {}; }
  static Range at_least(double x) { return {x, Range{}.hi, false, false}; }
  static Range above(double x) { return {x, Range{}.hi, true, false}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range open(double a, double b) { return {a, b, true, true}; }
  bool contains(double v) const;
  /// "(0, 180)", "[0, 1]", "(>= 0)", "(> 0)", "(any finite number)".
  std::string describe() const;
};

/// One key of a mapping and what its value takes, as messages show them (`azimuth`, `degrees`).
/// A table of these is the mapping's one list of keys: Map::allow checks against it and the
/// messages show it (braced).
struct KeyShape {
  std::string_view name;
  std::string_view takes;
};

/// `{k1: t1, k2: t2}`, or `{k1, k2}` with `names_only`.
std::string braced(std::span<const KeyShape> keys, bool names_only = false);

/// "a mapping with keys k1, k2, ..." and then `note`: what Value::map_with_keys allows.
std::string mapping_with_keys(std::initializer_list<std::string_view> keys, std::string_view note = "");

class Map;
class ValueList;

/// A node plus the key path that leads to it. Cheap to copy (the path is built when asked
/// for, from the parent's, which its children share).
class Value {
 public:
  /// The root of `doc`'s tree; `anchor` is where to point when it has no position.
  Value(const Document* doc, SourceMark anchor);

  /// The key path: `renders[0].camera.fov`.
  std::string path() const;
  const Document& doc() const { return *m_doc; }
  /// 1-based position for messages: a mapping value points at its key (`fov: 270` at `fov`),
  /// a list element at itself.
  SourceMark mark() const;

  [[noreturn]] void fail(const std::string& message) const;

  bool is_null() const { return kind() == YamlTree::Kind::Null; }
  bool is_scalar() const { return kind() == YamlTree::Kind::Scalar; }
  bool is_map() const { return kind() == YamlTree::Kind::Map; }
  bool is_sequence() const { return kind() == YamlTree::Kind::Sequence; }
  /// A scalar's text (quoted or not), "" for anything else.
  std::string_view text() const { return m_doc->tree->scalar(m_id); }
  /// A scalar (quoted or not) whose text is `word`.
  bool is_word(std::string_view word) const;
  /// How the value reads in a message: `270`, `"abc"`, `a mapping`, `a list`, `nothing`.
  std::string describe() const;

  /// A finite number inside `r`.
  double number(const Range& r = Range::any()) const;
  /// An integer in [lo, hi].
  std::int64_t integer(std::int64_t lo, std::int64_t hi) const;
  std::uint64_t unsigned64() const;
  bool boolean() const;
  /// Any scalar, as text (a non-empty string unless allow_empty); text that is not valid
  /// UTF-8 is an error naming the byte (names and paths: the writer could not give them back).
  std::string string(bool allow_empty = false) const;
  /// Any scalar, as text to draw: like string(), but each maximal invalid UTF-8 subsequence
  /// becomes U+FFFD (with_replacement_characters), so the result is UTF-8 and writes back as is.
  std::string drawn_text(bool allow_empty = false) const;
  /// One of the words of `table` (rows with .name and .value: EnumName in enum_names.h,
  /// ImageFormatInfo); a wrong word's message lists them all, in table order.
  template <class Table>
  auto choice(const Table& table) const;
  /// `[x, y, z]`, each inside `r`.
  Vec3 vec3(const Range& r = Range::any()) const;
  /// `[r, g, b]`, each inside `r`.
  Color color(const Range& r) const;

  /// The elements of a list of `min_size` to `max_size` elements; `allowed` says what the list
  /// should hold, for the message when it is not a list. The elements are made as they are
  /// read (no copy of a long list).
  ValueList list(const std::string& allowed, std::size_t min_size = 0,
                 std::size_t max_size = std::numeric_limits<std::size_t>::max()) const;
  /// The entries of a mapping (keys checked for duplicates); `allowed` is for the message when
  /// it is not one.
  Map map(const std::string& allowed = "a mapping") const;
  /// A mapping whose keys are all among `keys` (Map::allow), from the one list: when it is not
  /// a mapping the message says "a mapping with keys k1, k2, ..." and then `note`.
  Map map_with_keys(std::initializer_list<std::string_view> keys, std::string_view note = "") const;

 private:
  friend class Map;
  friend class ValueList;
  using Base = std::shared_ptr<const std::string>;
  Value(const Document* doc, YamlTree::Id id, Base base, std::string_view key, std::int64_t index, SourceMark anchor,
        bool anchor_is_key);
  YamlTree::Kind kind() const { return m_doc->tree->kind(m_id); }
  bool plain() const { return m_doc->tree->plain(m_id); }
  /// The value of mapping key `key` (at `key_mark`), element `index` of a list; `base` is
  /// this value's path, shared by its children.
  Value child(YamlTree::Id id, const Base& base, std::string_view key, SourceMark key_mark) const;
  Value element(YamlTree::Id id, const Base& base, std::size_t index) const;
  [[noreturn]] void wrong_type(const std::string& allowed) const;
  /// Counts `n` more visited nodes; throws here when the document's budget is exceeded.
  void visit(std::size_t n) const;
  Vec3 triple(const char* shape, const Range& r) const;
  const Document* m_doc;
  YamlTree::Id m_id;
  Base m_base;             ///< the parent's path; null for the root
  std::string_view m_key;  ///< the key that leads here (in the tree's text), or
  std::int64_t m_index;    ///< the list index that does (-1: none)
  SourceMark m_anchor;
  bool m_anchor_is_key;
};

/// The elements of a list, made as they are read.
class ValueList {
 public:
  class iterator {
   public:
    iterator(const ValueList* list, std::size_t i) : m_list(list), m_i(i) {}
    Value operator*() const { return (*m_list)[m_i]; }
    iterator& operator++() {
      ++m_i;
      return *this;
    }
    bool operator==(const iterator& o) const { return m_i == o.m_i; }
    bool operator!=(const iterator& o) const { return m_i != o.m_i; }

   private:
    const ValueList* m_list;
    std::size_t m_i;
  };

  explicit ValueList(const Value& list);
  std::size_t size() const { return m_size; }
  Value operator[](std::size_t i) const;
  iterator begin() const { return iterator(this, 0); }
  iterator end() const { return iterator(this, m_size); }

 private:
  Value m_list;
  Value::Base m_base;
  std::size_t m_size;
};

/// A mapping's entries, in document order (read from the tree; nothing is copied).
class Map {
 public:
  /// `self` must be a mapping whose keys are checked (Value::map()).
  explicit Map(Value self);

  /// Throws at the first key not in `keys`, listing them.
  void allow(std::initializer_list<std::string_view> keys) const;
  void allow(std::span<const KeyShape> keys) const;
  bool has(std::string_view key) const;
  std::optional<Value> get(std::string_view key) const;
  /// Throws "missing required key (allowed: `what`)" at the mapping's position.
  Value require(std::string_view key, const std::string& what) const;
  const Value& self() const { return m_self; }
  std::size_t size() const;

  /// Optional-key helpers: the value if present, else `fallback`.
  double number_or(std::string_view key, double fallback, const Range& r = Range::any()) const;
  std::int64_t integer_or(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  Vec3 vec3_or(std::string_view key, const Vec3& fallback, const Range& r = Range::any()) const;
  Color color_or(std::string_view key, const Color& fallback, const Range& r) const;
  template <class Table, class E>
  E choice_or(std::string_view key, E fallback, const Table& table) const {
    const auto v = get(key);
    return v ? v->choice(table) : fallback;
  }

 private:
  friend class Value;
  void allow_names(std::span<const std::string_view> keys) const;
  std::string_view key(std::size_t i) const;
  SourceMark key_mark(std::size_t i) const;
  Value entry(std::size_t i) const;
  Value m_self;
  Value::Base m_base;
};

/// "a, b or c" from a list of words (`sep` between all but the last two).
std::string join_words(const std::vector<std::string>& words, const char* last_sep = " or ", const char* sep = ", ");

template <class Table>
auto Value::choice(const Table& table) const {
  std::vector<std::string> names;
  for (const auto& row : table) {
    if (is_word(row.name)) return row.value;
    names.emplace_back(row.name);
  }
  if (is_scalar()) fail(describe() + " is not allowed (allowed: " + join_words(names) + ")");
  wrong_type(join_words(names));
}

}  // namespace tessera::config::detail
