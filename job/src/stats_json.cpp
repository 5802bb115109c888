#include <tessera/job/stats_json.h>

#include <tessera/atomic_output.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace tessera::job {
namespace {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "0";
  return format_number(v);
}

/// The times, derived rates and every counter of kRenderCounters (in its order), shared by
/// the totals and each render, one per line.
void counters(std::string& out, const RenderStats& s, double prepare_seconds, const char* indent) {
  const auto field = [&](const char* name, const std::string& value) {
    out += indent;
    out += quote(name) + ": " + value + ",\n";
  };
  field("wall_seconds", number(s.wall_seconds));
  field("prepare_seconds", number(prepare_seconds));
  field("samples_per_second", number(s.wall_seconds > 0 ? double(s.samples) / s.wall_seconds : 0.0));
  field("density_lookups", std::to_string(s.density_lookups()));
  field("lookups_per_real_collision",
        number(s.real_collisions > 0 ? double(s.free_flight_lookups) / double(s.real_collisions) : 0.0));
  for (const RenderCounter& c : kRenderCounters) field(c.name, std::to_string(s.*c.field));
  out += indent;
  out += quote("threads") + ": " + std::to_string(s.threads);
}

/// ",\n<indent>"warnings": [...]" (RenderRecord::warnings, each prefixed by `prefix`).
void warnings(std::string& out, const std::vector<std::string>& list, const char* indent) {
  out += ",\n";
  out += indent;
  out += "\"warnings\": [";
  for (std::size_t i = 0; i < list.size(); ++i) out += (i ? ", " : "") + quote(list[i]);
  out += "]";
}

}  // namespace

std::string stats_json(const std::vector<RenderRecord>& records) {
  // Totals: counters combine by their rule (stats.h), times add up; threads is the largest used
  RenderStats total;
  double prepare_total = 0.0;
  for (const auto& r : records) {
    total.add_counters(r.stats);
    total.wall_seconds += r.stats.wall_seconds;
    total.threads = std::max(total.threads, r.stats.threads);
    prepare_total += r.prepare_seconds;
  }

  std::string out = "{\n";
  counters(out, total, prepare_total, "  ");
  // Top level: every render's warnings, each naming its render
  std::vector<std::string> all_warnings;
  for (const auto& r : records)
    for (const std::string& w : r.warnings) all_warnings.push_back(r.name + ": " + w);
  warnings(out, all_warnings, "  ");
  out += ",\n  \"renders\": [";
  for (std::size_t i = 0; i < records.size(); ++i) {
    const RenderRecord& r = records[i];
    out += i == 0 ? "\n    {\n" : ",\n    {\n";
    out += "      \"name\": " + quote(r.name) + ",\n";
    out += "      \"width\": " + std::to_string(r.width) + ",\n";
    out += "      \"height\": " + std::to_string(r.height) + ",\n";
    out += "      \"spp\": " + std::to_string(r.spp) + ",\n";
    out += "      \"denoise_seconds\": " + number(r.denoise_seconds) + ",\n";
    out += "      \"device\": " + quote(r.device) + ",\n";
    out += "      \"outputs\": [";
    for (std::size_t j = 0; j < r.outputs.size(); ++j) out += (j ? ", " : "") + quote(r.outputs[j]);
    out += "],\n";
    counters(out, r.stats, r.prepare_seconds, "      ");
    warnings(out, r.warnings, "      ");
    out += "\n    }";
  }
  out += records.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

void write_stats_json(const std::string& path, const std::vector<RenderRecord>& records) {
  const std::filesystem::path p(path);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  try {
    write_file_atomically(path, stats_json(records));
  } catch (const AtomicOutputError& e) {
    throw std::runtime_error("cannot write statistics file '" + path + "': " + e.fault());
  }
}

}  // namespace tessera::job
