#pragma once
// Private: a YAML document as a compact tree, built from yaml-cpp's parse events (the event
// parser holds no tree). YAML::Load spends about 500 bytes per node (a 4 MiB flow list of
// one-character scalars took about 1 GB); here a node is 20 bytes, a reference to it from its
// list or mapping 4 more, and scalars share one text buffer. The nodes are counted while the
// tree is built and bounded by the caller (kMaxYamlNodes, 2^21: about 64 MiB with the
// building stack; docs/config.md "Limits").
#include <tessera/config/config_error.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tessera::config::detail {

class YamlTree {
 public:
  using Id = std::uint32_t;
  enum class Kind : std::uint8_t { Null, Scalar, Sequence, Map };

  /// The first document of `text` (a second one is the caller's concern: second_document()).
  /// An empty document is a single Null root without a position. An alias is the node it
  /// names (shared, as in yaml-cpp's trees). Throws YAML::Exception on bad syntax
  /// (YAML::DeepRecursion past yaml-cpp's nesting limit) and ConfigError at the node past
  /// `max_nodes` nodes (list elements, mapping keys and values, aliases each counted).
  static YamlTree parse(const std::string& text, const std::string& file, std::size_t max_nodes);

  Id root() const { return 0; }
  Kind kind(Id n) const { return m_nodes[n].kind; }
  /// A plain (unquoted, untagged) scalar: the only kind that may be a number or a boolean.
  bool plain(Id n) const { return m_nodes[n].plain; }
  /// 1-based position; line 0 when the node has none (an empty document).
  SourceMark mark(Id n) const {
    return SourceMark{static_cast<int>(m_nodes[n].line), static_cast<int>(m_nodes[n].column)};
  }
  std::string_view scalar(Id n) const;
  /// Elements of a list, entries of a mapping; 0 otherwise.
  std::size_t size(Id n) const;
  Id element(Id n, std::size_t i) const { return m_children[m_nodes[n].first + i]; }
  Id key(Id n, std::size_t i) const { return m_children[m_nodes[n].first + 2 * i]; }
  Id value(Id n, std::size_t i) const { return m_children[m_nodes[n].first + 2 * i + 1]; }
  /// Nodes and child references held (for tests and messages).
  std::size_t node_count() const { return m_nodes.size(); }
  /// The first node (in document order) with an explicit tag, as yaml-cpp reports it (e.g.
  /// "!foo", "tag:yaml.org,2002:binary"), and where it starts; tag "" when there is none. The
  /// non-specific tags yaml-cpp gives every untagged node ("?" plain, "!" quoted) do not count.
  const std::string& first_tag() const { return m_first_tag; }
  SourceMark first_tag_mark() const { return m_first_tag_mark; }

 private:
  friend class YamlTreeBuilder;
  struct Node {
    std::uint32_t line = 0, column = 0;
    std::uint32_t first = 0;  ///< scalar: offset in m_text; list or map: index in m_children
    std::uint32_t count = 0;  ///< scalar: length; list: elements; map: keys and values
    Kind kind = Kind::Null;
    bool plain = false;
  };
  std::vector<Node> m_nodes;
  std::vector<Id> m_children;
  std::string m_text;
  std::string m_first_tag;
  SourceMark m_first_tag_mark;
};

}  // namespace tessera::config::detail
