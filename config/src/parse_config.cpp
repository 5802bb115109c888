// The top level of a config: parse_config, load_config, `tessera:` and `volume:`.
#include <tessera/config/config.h>
#include <tessera/config/render_defaults.h>
#include <tessera/loop_bounds.h>

#include "enum_names.h"
#include "parsers.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/exceptions.h>

#include <tessera/message_text.h>
#include <tessera/regular_file.h>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

namespace tessera::config {
namespace fs = std::filesystem;
using tessera::format_number;
using detail::Range;
using detail::Value;

namespace {

/// The top-level keys, in the order messages list them.
const std::initializer_list<std::string_view> kTopKeys = {"tessera", "volume", "renders"};

SourceMark from_yaml(const YAML::Mark& m) {
  if (m.is_null() || m.line < 0) return {};
  return SourceMark{m.line + 1, m.column + 1};
}

std::string too_large(std::uint64_t bytes) {
  return "config is " + std::to_string(bytes) + " bytes (allowed: at most " + std::to_string(detail::kMaxConfigBytes) +
         " bytes, 4 MiB)";
}

Config parse_root(const detail::Document& doc) {
  const Value top(&doc, SourceMark{1, 1});
  if (top.is_null()) {
    throw ConfigError(doc.file, {}, "", "empty config (allowed: " + detail::mapping_with_keys(kTopKeys) + ")");
  }
  const detail::Map m = top.map_with_keys(kTopKeys);

  Config c;
  c.path = doc.file;
  if (const auto g = m.get("tessera")) c.global = detail::parse_global(*g);
  if (const auto v = m.get("volume")) c.volume = detail::parse_volume(*v);

  // Renders, names unique
  const auto renders = m.require("renders", "a list of renders")
                           .list("a list of renders (mappings with field, name, camera, "
                                 "transfer_function, ...)",
                                 1);
  // A render without a name is named after its field, never taking a name the file gives
  std::unordered_set<std::string> taken;
  for (const Value& r : renders)
    if (r.is_map())
      if (const auto n = r.map().get("name"); n && n->is_scalar()) taken.emplace(n->text());
  const auto unique_name = [&taken](const std::string& field) {
    const std::string base = default_render_name(field);
    std::string name = base;
    for (int k = 2; taken.count(name) != 0; ++k) {
      const std::string digits = std::to_string(k);
      name = base.substr(0, RenderSpec::kMaxName - 1 - digits.size());
      name += '_';
      name += digits;
    }
    taken.insert(name);
    return name;
  };
  std::unordered_map<std::string, SourceMark> name_marks;  // name -> where first used
  for (const Value& r : renders) {
    RenderSpec spec = detail::parse_render(r, unique_name);
    // With a budget the EXR shows the samples each pixel got, unless the render says otherwise
    if (c.global.budget > 0.0 && spec.output.has_format(ImageFormat::Exr)) {
      const auto out = r.map().get("output");
      if (!out || !out->map().get("samples")) spec.output.samples = true;
    }
    if (const auto name = r.map().get("name")) {
      const auto [it, fresh] = name_marks.emplace(spec.name, name->mark());
      if (!fresh) {
        name->fail("duplicate render name \"" + detail::cut_for_message(spec.name) + "\" (first used at line " +
                   std::to_string(it->second.line) + "; allowed: a name used once)");
      }
    }
    c.renders.push_back(std::move(spec));
  }
  return c;
}

}  // namespace

namespace detail {

GlobalOptions parse_global(const Value& v) {
  const Map m = v.map_with_keys({"output_dir", "on_error", "threads", "render_final_step", "max_failures", "time_limit",
                                 "memory_limit_mb", "distribution", "brick_cache", "budget", "device", "cuda_device"});
  GlobalOptions g;
  if (const auto d = m.get("output_dir")) {
    g.output_dir = d->string();
    for (const char c : g.output_dir) {
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
        d->fail(d->describe() + " contains a control character (allowed: printable characters)");
      }
    }
  }
  g.on_error = m.choice_or("on_error", g.on_error, kOnErrorNames);
  g.threads = static_cast<int>(m.integer_or("threads", g.threads, 0, 65536));
  g.render_final_step = m.boolean_or("render_final_step", g.render_final_step);
  g.max_failures = static_cast<int>(m.integer_or("max_failures", g.max_failures, 1, std::numeric_limits<int>::max()));
  g.time_limit = m.number_or("time_limit", g.time_limit, Range::closed(0.0, GlobalOptions::kMaxTimeLimit));
  g.memory_limit_mb = m.integer_or("memory_limit_mb", g.memory_limit_mb, 0, GlobalOptions::kMaxMemoryLimitMb);
  g.distribution = m.choice_or("distribution", g.distribution, kDistributionNames);
  g.brick_cache = m.number_or("brick_cache", g.brick_cache, Range{0.0, 1.0, true, false});
  g.budget = m.number_or("budget", g.budget, Range{0.0, GlobalOptions::kMaxBudget, true, false});
  g.device = m.choice_or("device", g.device, kDeviceNames);
  g.cuda_device = static_cast<int>(m.integer_or("cuda_device", g.cuda_device, -1, GlobalOptions::kMaxCudaDevice));
  return g;
}

VolumeSpec parse_volume(const Value& v) {
  const Map m =
      v.map_with_keys({"file", "dims", "dtype", "spacing", "origin", "byte_order", "header_bytes", "association"});
  VolumeSpec s;
  s.file = resolve_existing_file(m.require("file", "a file name, relative to this YAML file"));

  // Dims, and a size that fits in memory arithmetic
  const auto dims = m.require("dims", "[nx, ny, nz], integers >= 1").list("[nx, ny, nz]", 3, 3);
  for (int i = 0; i < 3; ++i) s.dims[i] = dims[i].integer(1, std::int64_t(1) << 31);
  s.dtype = m.require("dtype", join_words(names_of(kDTypeNames))).choice(kDTypeNames);
  const double bytes = double(s.dims[0]) * double(s.dims[1]) * double(s.dims[2]) * 8.0;
  if (bytes > double(std::int64_t(1) << 50)) {
    m.get("dims")->fail("too many vertices (allowed: at most 2^47 vertices)");
  }

  // Spacing and origin within the bounds that keep a voxel resolvable (tessera/loop_bounds.h)
  s.spacing = m.vec3_or("spacing", s.spacing, Range::closed(kMinSpacing, kMaxSpacing));
  s.origin = m.vec3_or("origin", s.origin);
  s.association = m.choice_or("association", s.association, kAssociationNames);
  {
    const double h = std::min({s.spacing.x, s.spacing.y, s.spacing.z});
    const double lim = kMaxCoordinateVoxels * h;
    Vec3 far = s.origin;
    // The far corner of the vertices, or of the cells (one spacing further)
    const std::int64_t last = s.association == Association::Cell ? 0 : 1;
    for (int a = 0; a < 3; ++a) far[a] += static_cast<double>(s.dims[a] - last) * s.spacing[a];
    const auto max_abs = [](const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); };
    if (!(max_abs(s.origin) <= lim) || !(max_abs(far) <= lim)) {
      const std::string why = "puts the data (far corner [" + format_number(far.x) + ", " + format_number(far.y) +
                              ", " + format_number(far.z) + "]) beyond 2^40 smallest spacings (" + format_number(lim) +
                              ") from 0, where a double no longer resolves a voxel";
      const auto o = m.get("origin"), sp = m.get("spacing");
      if (o && !(max_abs(s.origin) <= lim)) o->fail(why);
      (sp ? *sp : *m.get("dims"))
          .fail("with dims " + std::to_string(s.dims[0]) + "x" + std::to_string(s.dims[1]) + "x" +
                std::to_string(s.dims[2]) + " " + why);
    }
  }
  s.byte_order = m.choice_or("byte_order", s.byte_order, kByteOrderNames);
  s.header_bytes = m.integer_or("header_bytes", 0, 0, std::numeric_limits<std::int64_t>::max());
  return s;
}

std::string resolve_existing_file(const Value& v) {
  const std::string name = v.string();
  if (name.find('\0') != std::string::npos) {
    v.fail(v.describe() + " contains a NUL character (allowed: a file name)");
  }
  fs::path p(name);
  if (p.is_relative() && !v.doc().base_dir.empty()) p = fs::path(v.doc().base_dir) / p;
  std::error_code ec;
  p = fs::absolute(p, ec).lexically_normal();
  const std::string shown = shown_path(p.string());
  if (ec) v.fail("cannot resolve " + v.describe() + ": " + ec.message());
  // Only regular files: a FIFO would block the reader, /dev/zero would never end
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) {
      v.fail("file not found: " + shown +
             " (allowed: an existing file, relative names are "
             "relative to the YAML file's directory)");
    }
    v.fail("cannot access " + shown + ": " + std::strerror(err));
  }
  if (S_ISDIR(st.st_mode)) v.fail(shown + " is a directory (allowed: a file)");
  if (!S_ISREG(st.st_mode)) {
    v.fail(shown + " is " + file_kind_name(st.st_mode) + " (allowed: a regular file)");
  }
  return p.string();
}

}  // namespace detail

Config parse_config(const std::string& yaml_text, const std::string& file_name_for_messages,
                    const std::string& base_dir) {
  detail::Document doc{file_name_for_messages, base_dir};
  doc.node_budget = detail::node_budget(yaml_text.size());
  if (yaml_text.size() > detail::kMaxConfigBytes) {
    throw ConfigError(doc.file, {}, "", too_large(yaml_text.size()));
  }
  try {
    // One document: a second one (after ---) is refused unless it is empty
    // The tree is built from the parser's events, its nodes counted as they come
    // (yaml_tree.h): a file within the size cap cannot make the parse take unbounded memory
    const detail::YamlTree tree = detail::YamlTree::parse(yaml_text, doc.file, detail::kMaxYamlNodes);
    doc.tree = &tree;
    if (const auto second = detail::second_document(yaml_text)) {
      throw ConfigError(doc.file, *second, "",
                        "a second YAML document starts here (allowed: one document per config "
                        "file)");
    }
    if (const auto tag = detail::first_explicit_tag(tree)) {
      throw ConfigError(doc.file, tag->mark, "",
                        "YAML tag " + tag->tag +
                            " is not supported (allowed: untagged values; "
                            "quote a value that starts with '!')");
    }
    return parse_root(doc);
  } catch (const YAML::DeepRecursion& e) {
    throw ConfigError(doc.file, from_yaml(e.mark), "",
                      "invalid YAML: nested too deeply (allowed: the YAML parser's limit of " +
                          std::to_string(e.depth()) + " levels of recursion)");
  } catch (const YAML::Exception& e) {
    // Syntax errors, and anything yaml-cpp itself rejects while walking the tree
    throw ConfigError(doc.file, from_yaml(e.mark), "", "invalid YAML: " + e.msg);
  }
}

Config load_config(const std::string& path) {
  // A regular file of at most kMaxConfigBytes, checked before reading
  std::optional<RegularFile> file;
  try {
    file.emplace(path);
  } catch (const std::exception& e) {
    // The path leads the message already: not a second time (the reason names it first)
    std::string why = e.what();
    if (why.rfind(path + ": ", 0) == 0) why.erase(0, path.size() + 2);
    throw ConfigError(path, {}, "", "cannot open config file: " + message_quoting(std::move(why), path));
  }
  if (file->size() > detail::kMaxConfigBytes) throw ConfigError(path, {}, "", too_large(file->size()));
  std::string text(static_cast<std::size_t>(file->size()), '\0');
  try {
    file->read_at(0, text.data(), text.size());
  } catch (const std::exception& e) {
    throw ConfigError(path, {}, "", std::string("cannot read config file: ") + e.what());
  }
  return parse_config(text, path, fs::path(path).parent_path().string());
}

const RenderSpec* Config::find_render(const std::string& name) const {
  for (const auto& r : renders)
    if (r.name == name) return &r;
  return nullptr;
}

const char* on_error_name(OnError e) { return detail::name_of(detail::kOnErrorNames, e); }

}  // namespace tessera::config
