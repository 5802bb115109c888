#include "cli_options.h"

#include "domain_split.h"

#include "busy_work.h"

#include <charconv>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#ifndef TESSERA_HEAT_SOURCE_CONFIG
#define TESSERA_HEAT_SOURCE_CONFIG ""
#endif
#ifndef TESSERA_HEAT_INSTALL_CONFIG
#define TESSERA_HEAT_INSTALL_CONFIG ""
#endif

namespace heat {
namespace {

std::int64_t parse_int(std::string_view flag, const char* text, std::int64_t min,
                       std::int64_t max = std::numeric_limits<std::int64_t>::max()) {
  const std::string_view s(text);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v < min || v > max)
    throw std::invalid_argument(
        std::string(flag) + " needs an integer >= " + std::to_string(min) +
        (max < std::numeric_limits<std::int64_t>::max() ? " and <= " + std::to_string(max) : "") + ", got '" +
        std::string(s) + "'");
  return v;
}

}  // namespace

std::string usage() {
  return "usage: [mpirun -n P] tessera-heat [--config FILE] [--steps N] [--grid NX NY NZ] [--output-dir DIR] [--dump "
         "FILE]\n"
         "                    [--work-ms N] [--domains-per-rank N] [--cell] [--amr [--levels 2|3] [--ratio 2|4]]\n"
         "                    [--device cpu|cuda]\n"
         "  --config FILE     Tessera YAML config (default: the project's configs/heat.yaml)\n"
         "  --steps N         time steps after the initial state (default 100)\n"
         "  --grid NX NY NZ   global grid vertices, each >= 3 (default 64 64 64)\n"
         "  --output-dir DIR  write images under DIR instead of the config's output_dir\n"
         "  --dump FILE       at the end, write the global field to FILE (raw float32, i fastest)\n"
         "  --work-ms N       add N ms of computation to each step (0..60000, default 0): a slower simulation\n"
         "  --domains-per-rank N  publish each rank's array as N uneven domains (1..1024; zero copy)\n"
         "  --cell            publish the values as cell data (cells centred on the vertices)\n"
         "  --amr             add refined levels that follow a moving heat source (docs/miniapp.md)\n"
         "  --levels L        with --amr: levels in all, 2 or 3 (default 2)\n"
         "  --ratio R         with --amr: refinement ratio between levels, 2 or 4 (default 2)\n"
         "  --device D        where the solver runs and the field lives: cpu (default) or cuda (one GPU per rank,\n"
         "                    by node-local rank modulo the visible devices; the field stays in device memory and\n"
         "                    is rendered in place; needs a CUDA build; not with --amr, --cell or "
         "--domains-per-rank)\n";
}

Options parse_options(int argc, const char* const* argv) {
  Options o;
  bool levels_given = false;
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
      o.steps = parse_int(a, argv[++i], 0);
    } else if (a == "--grid") {
      need(3);
      for (int k = 0; k < 3; ++k) o.grid[k] = parse_int(a, argv[++i], 3);
    } else if (a == "--output-dir") {
      need(1);
      o.output_dir = argv[++i];
      if (o.output_dir->empty()) throw std::invalid_argument("--output-dir needs a non-empty directory");
    } else if (a == "--work-ms") {
      need(1);
      o.work_ms = parse_int(a, argv[++i], 0, kMaxWorkMs);
    } else if (a == "--cell") {
      o.cell = true;
    } else if (a == "--amr") {
      o.amr = true;
    } else if (a == "--levels") {
      need(1);
      o.levels = static_cast<int>(parse_int(a, argv[++i], 2, 3));
      levels_given = true;
    } else if (a == "--ratio") {
      need(1);
      o.ratio = static_cast<int>(parse_int(a, argv[++i], 2, 4));
      if (o.ratio == 3) throw std::invalid_argument("--ratio needs 2 or 4, got '3'");
      levels_given = true;
    } else if (a == "--domains-per-rank") {
      need(1);
      o.domains_per_rank = parse_int(a, argv[++i], 1, kMaxDomainsPerRank);
    } else if (a == "--device") {
      need(1);
      const std::string_view d = argv[++i];
      if (d == "cpu") o.device = Device::cpu;
      else if (d == "cuda") o.device = Device::cuda;
      else throw std::invalid_argument("--device needs cpu or cuda, got '" + std::string(d) + "'");
    } else if (a == "--dump") {
      need(1);
      o.dump = argv[++i];
      if (o.dump->empty()) throw std::invalid_argument("--dump needs a non-empty file name");
    } else {
      throw std::invalid_argument("unknown argument '" + std::string(a) + "'");
    }
  }
  if (levels_given && !o.amr) throw std::invalid_argument("--levels and --ratio need --amr");
  if (o.device == Device::cuda && (o.amr || o.cell || o.domains_per_rank > 0))
    throw std::invalid_argument(std::string("--device cuda publishes one block per rank: ") +
                                (o.amr    ? "--amr"
                                 : o.cell ? "--cell"
                                          : "--domains-per-rank") +
                                " needs --device cpu");
  return o;
}

std::string default_config_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<fs::path> candidates;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / ".." / "share" / "tessera" / "configs" / "heat.yaml");
  candidates.emplace_back(TESSERA_HEAT_SOURCE_CONFIG);
  candidates.emplace_back(TESSERA_HEAT_INSTALL_CONFIG);
  for (const fs::path& p : candidates)
    if (!p.empty() && fs::is_regular_file(p, ec)) return fs::weakly_canonical(p, ec).string();
  return "";
}

}  // namespace heat
