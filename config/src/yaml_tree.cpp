#include "yaml_tree.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <sstream>

namespace tessera::config::detail {

/// Builds a YamlTree from the parser's events: each node is appended when it starts; the
/// children of the open lists and mappings wait on one stack and are copied into the tree's
/// child array when their container ends.
class YamlTreeBuilder final : public YAML::EventHandler {
 public:
  YamlTreeBuilder(YamlTree& tree, const std::string& file, std::size_t max_nodes, std::size_t reserve)
      : m_tree(tree), m_file(file), m_max_nodes(max_nodes) {
    m_pending.reserve(reserve);
  }

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t anchor) override { add(m, YamlTree::Kind::Null, anchor); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t anchor) override {
    count(m);
    // yaml-cpp refuses an alias to an undefined anchor before calling this
    if (anchor < m_anchors.size() && !m_open.empty()) m_pending.push_back(m_anchors[anchor]);
  }
  void OnScalar(const YAML::Mark& m, const std::string& tag, YAML::anchor_t anchor, const std::string& value) override {
    note_tag(m, tag);
    YamlTree::Node& n = add(m, YamlTree::Kind::Scalar, anchor);
    n.plain = tag == "?";
    n.first = static_cast<std::uint32_t>(m_tree.m_text.size());
    n.count = static_cast<std::uint32_t>(value.size());
    m_tree.m_text += value;
  }
  void OnSequenceStart(const YAML::Mark& m, const std::string& tag, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    note_tag(m, tag);
    open(m, YamlTree::Kind::Sequence, anchor);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& m, const std::string& tag, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    note_tag(m, tag);
    open(m, YamlTree::Kind::Map, anchor);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Open {
    YamlTree::Id id;
    std::size_t first_pending;
  };

  void note_tag(const YAML::Mark& m, const std::string& tag) {
    if (!m_tree.m_first_tag.empty() || tag.empty() || tag == "?" || tag == "!") return;
    m_tree.m_first_tag = tag;
    m_tree.m_first_tag_mark = SourceMark{m.line + 1, m.column + 1};
  }

  void count(const YAML::Mark& m) {
    if (++m_count <= m_max_nodes) return;
    throw ConfigError(m_file, SourceMark{m.line + 1, m.column + 1}, "",
                      "the config has more than " + std::to_string(m_max_nodes) + " YAML nodes (allowed: at most " +
                          std::to_string(m_max_nodes) +
                          " list elements, keys, values and aliases, which bounds the memory of "
                          "loading it)");
  }

  YamlTree::Node& add(const YAML::Mark& m, YamlTree::Kind kind, YAML::anchor_t anchor) {
    count(m);
    const auto id = static_cast<YamlTree::Id>(m_tree.m_nodes.size());
    YamlTree::Node n;
    n.line = static_cast<std::uint32_t>(m.line + 1);
    n.column = static_cast<std::uint32_t>(m.column + 1);
    n.kind = kind;
    m_tree.m_nodes.push_back(n);
    if (!m_open.empty()) m_pending.push_back(id);
    if (anchor != 0) {
      if (anchor >= m_anchors.size()) m_anchors.resize(anchor + 1, 0);
      m_anchors[anchor] = id;
    }
    return m_tree.m_nodes.back();
  }

  void open(const YAML::Mark& m, YamlTree::Kind kind, YAML::anchor_t anchor) {
    const auto id = static_cast<YamlTree::Id>(m_tree.m_nodes.size());
    add(m, kind, anchor);
    m_open.push_back(Open{id, m_pending.size()});
  }

  void close() {
    const Open o = m_open.back();
    m_open.pop_back();
    YamlTree::Node& n = m_tree.m_nodes[o.id];
    n.first = static_cast<std::uint32_t>(m_tree.m_children.size());
    n.count = static_cast<std::uint32_t>(m_pending.size() - o.first_pending);
    m_tree.m_children.insert(m_tree.m_children.end(), m_pending.begin() + static_cast<std::ptrdiff_t>(o.first_pending),
                             m_pending.end());
    m_pending.resize(o.first_pending);
  }

  YamlTree& m_tree;
  const std::string& m_file;
  std::size_t m_max_nodes;
  std::size_t m_count = 0;
  std::vector<Open> m_open;
  std::vector<YamlTree::Id> m_pending;
  std::vector<YamlTree::Id> m_anchors;  ///< yaml-cpp's anchor number -> node
};

YamlTree YamlTree::parse(const std::string& text, const std::string& file, std::size_t max_nodes) {
  YamlTree tree;
  // Room for the most nodes the text can hold, reserved (address space; pages are touched
  // as nodes arrive), so no vector is copied while growing
  const std::size_t most = std::min(max_nodes, text.size() + 1);
  tree.m_nodes.reserve(most);
  tree.m_children.reserve(most);
  tree.m_text.reserve(text.size());
  {
    std::istringstream in(text);
    YAML::Parser parser(in);
    YamlTreeBuilder builder(tree, file, max_nodes, most);
    parser.HandleNextDocument(builder);
  }
  if (tree.m_nodes.empty()) tree.m_nodes.push_back(Node{});  // an empty document: null root
  return tree;
}

std::string_view YamlTree::scalar(Id n) const {
  const Node& x = m_nodes[n];
  if (x.kind != Kind::Scalar) return {};
  return std::string_view(m_text).substr(x.first, x.count);
}

std::size_t YamlTree::size(Id n) const {
  const Node& x = m_nodes[n];
  if (x.kind == Kind::Sequence) return x.count;
  if (x.kind == Kind::Map) return x.count / 2;
  return 0;
}

}  // namespace tessera::config::detail
