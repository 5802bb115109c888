// A YAML mapping read with file:line:column errors (yaml_reader.h, Map): its keys and
// entries, the keys it allows, and the lookups with defaults.
#include "yaml_reader.h"

#include <string>
#include <string_view>
#include <vector>

namespace tessera::config::detail {

// ---------------------------------------------------------------------------------------------
// Map

Map::Map(Value self) : m_self(std::move(self)), m_base(std::make_shared<const std::string>(m_self.path())) {}

std::size_t Map::size() const { return m_self.m_doc->tree->size(m_self.m_id); }

std::string_view Map::key(std::size_t i) const {
  const YamlTree& t = *m_self.m_doc->tree;
  return t.scalar(t.key(m_self.m_id, i));
}

SourceMark Map::key_mark(std::size_t i) const {
  const YamlTree& t = *m_self.m_doc->tree;
  return t.mark(t.key(m_self.m_id, i));
}

Value Map::entry(std::size_t i) const {
  const YamlTree& t = *m_self.m_doc->tree;
  return m_self.child(t.value(m_self.m_id, i), m_base, key(i), key_mark(i));
}

Map Value::map_with_keys(std::initializer_list<std::string_view> keys, std::string_view note) const {
  Map m = map(mapping_with_keys(keys, note));
  m.allow(keys);
  return m;
}

void Map::allow(std::initializer_list<std::string_view> keys) const { allow_names({keys.begin(), keys.size()}); }

void Map::allow(std::span<const KeyShape> keys) const {
  std::vector<std::string_view> names;
  for (const KeyShape& k : keys) names.push_back(k.name);
  allow_names(names);
}

void Map::allow_names(std::span<const std::string_view> keys) const {
  for (std::size_t i = 0; i < size(); ++i) {
    bool known = false;
    for (auto k : keys) known = known || k == key(i);
    if (known) continue;
    std::string list;
    for (auto k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
    throw ConfigError(m_self.doc().file, key_mark(i), entry(i).path(), "unknown key (allowed: " + list + ")");
  }
}

bool Map::has(std::string_view k) const {
  for (std::size_t i = 0; i < size(); ++i)
    if (key(i) == k) return true;
  return false;
}

std::optional<Value> Map::get(std::string_view k) const {
  for (std::size_t i = 0; i < size(); ++i)
    if (key(i) == k) return entry(i);
  return std::nullopt;
}

Value Map::require(std::string_view key, const std::string& what) const {
  if (auto v = get(key)) return *v;
  const std::string path = m_self.path().empty() ? std::string(key) : m_self.path() + "." + std::string(key);
  throw ConfigError(m_self.doc().file, m_self.mark(), path, "missing required key (allowed: " + what + ")");
}

double Map::number_or(std::string_view key, double fallback, const Range& r) const {
  const auto v = get(key);
  return v ? v->number(r) : fallback;
}

std::int64_t Map::integer_or(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) const {
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
