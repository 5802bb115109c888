#include "shell_options.h"

#include <charconv>
#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#ifndef TESSERA_HEAT_SHELL_SOURCE_CONFIG
#define TESSERA_HEAT_SHELL_SOURCE_CONFIG ""
#endif
#ifndef TESSERA_HEAT_SHELL_INSTALL_CONFIG
#define TESSERA_HEAT_SHELL_INSTALL_CONFIG ""
#endif

namespace heat {
namespace {

std::int64_t parse_int(std::string_view flag, const char* text, std::int64_t min, std::int64_t max) {
  const std::string_view s(text);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v < min || v > max)
    throw std::invalid_argument(std::string(flag) + " needs an integer >= " + std::to_string(min) +
                                " and <= " + std::to_string(max) + ", got '" + std::string(s) + "'");
  return v;
}

}  // namespace

std::string shell_usage() {
  return "usage: [mpirun -n P] tessera-heat-shell [--config FILE] [--steps N] [--grid NR NTHETA NZ] [--output-dir "
         "DIR]\n"
         "  --config FILE          Tessera YAML config (default: the project's configs/heat_shell.yaml)\n"
         "  --steps N              time steps after the initial state (default 100)\n"
         "  --grid NR NTHETA NZ    vertices along the radius, the angle (periodic) and the height,\n"
         "                         each 3..4096, NTHETA >= the ranks (default 24 96 32)\n"
         "  --output-dir DIR       write images under DIR instead of the config's output_dir\n";
}

ShellOptions parse_shell_options(int argc, const char* const* argv) {
  ShellOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const auto need = [&](int n) {
      if (i + n >= argc)
        throw std::invalid_argument(std::string(a) + " needs " + std::to_string(n) + " value" + (n > 1 ? "s" : ""));
    };
    if (a == "--help" || a == "-h") {
      o.help = true;
    } else if (a == "--config") {
      need(1);
      o.config = argv[++i];
    } else if (a == "--steps") {
      need(1);
      o.steps = parse_int(a, argv[++i], 0, std::int64_t{1} << 40);
    } else if (a == "--grid") {
      need(3);
      for (int k = 0; k < 3; ++k) o.grid[k] = parse_int(a, argv[++i], 3, kMaxShellAxis);
    } else if (a == "--output-dir") {
      need(1);
      o.output_dir = argv[++i];
      if (o.output_dir->empty()) throw std::invalid_argument("--output-dir needs a non-empty directory");
    } else {
      throw std::invalid_argument("unknown argument '" + std::string(a) + "'");
    }
  }
  return o;
}

std::string default_shell_config_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<fs::path> candidates;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / ".." / "share" / "tessera" / "configs" / "heat_shell.yaml");
  candidates.emplace_back(TESSERA_HEAT_SHELL_SOURCE_CONFIG);
  candidates.emplace_back(TESSERA_HEAT_SHELL_INSTALL_CONFIG);
  for (const fs::path& p : candidates)
    if (!p.empty() && fs::is_regular_file(p, ec)) return fs::weakly_canonical(p, ec).string();
  return "";
}

}  // namespace heat
