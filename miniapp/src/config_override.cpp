#include "config_override.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace heat {
namespace {

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::string replace_output_dir(const std::string& yaml, const std::string& dir) {
  std::vector<std::string> lines;
  std::istringstream in(yaml);
  for (std::string line; std::getline(in, line);) lines.push_back(line);

  static const std::regex block_head(R"(^tessera\s*:\s*(#.*)?$)");
  static const std::regex flow_head(R"(^tessera\s*:\s*\{)");
  static const std::regex output_key(R"(^(\s+)output_dir\s*:.*$)");
  static const std::regex flow_value(R"(output_dir\s*:\s*("[^"]*"|'[^']*'|[^,}]*))");
  static const std::regex child(R"(^(\s+)\S.*$)");
  const std::string entry = "output_dir: " + quoted(dir);

  bool done = false;
  for (std::size_t n = 0; n < lines.size() && !done; ++n) {
    // Flow mapping on one line: tessera: {on_error: warn, ...}
    if (std::regex_search(lines[n], flow_head)) {
      std::smatch m;
      if (std::regex_search(lines[n], m, flow_value))
        lines[n].replace(static_cast<std::size_t>(m.position(0)), static_cast<std::size_t>(m.length(0)), entry);
      else
        lines[n].insert(lines[n].find('{') + 1, entry + ", ");
      done = true;
      break;
    }
    if (!std::regex_match(lines[n], block_head)) continue;
    // Block mapping: its children are the indented lines up to the next top-level key.
    std::string indent;
    for (std::size_t c = n + 1; c < lines.size(); ++c) {
      const std::string& l = lines[c];
      const std::size_t first = l.find_first_not_of(" \t");
      if (first == std::string::npos || l[first] == '#') continue;
      if (first == 0) break;
      std::smatch m;
      if (indent.empty() && std::regex_match(l, m, child)) indent = m[1].str();
      if (std::regex_match(l, m, output_key)) {
        lines[c] = m[1].str() + entry;
        done = true;
        break;
      }
    }
    if (!done)  // the one case that shifts the lines below
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(n + 1), (indent.empty() ? "  " : indent) + entry);
    done = true;
  }
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  if (!done) out += "tessera: {" + entry + "}\n";  // no tessera block at all: add one at the end
  return out;
}

std::string write_config_with_output_dir(const std::string& config_path, const std::string& dir) {
  namespace fs = std::filesystem;
  std::ifstream in(config_path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read config '" + config_path + "'");
  std::stringstream text;
  text << in.rdbuf();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory '" + dir + "': " + ec.message());
  const fs::path copy = fs::path(dir) / "tessera_heat_config.yaml";
  std::ofstream out(copy, std::ios::binary | std::ios::trunc);
  // The note goes last, so that every line of the config keeps its number.
  out << replace_output_dir(text.str(), dir) << "# tessera-heat --output-dir: " << config_path
      << " with tessera.output_dir replaced\n";
  if (!out.flush()) throw std::runtime_error("cannot write '" + copy.string() + "'");
  return copy.string();
}

}  // namespace heat
