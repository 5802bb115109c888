#include "parse_args.h"

#include <tessera/scene.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

namespace tessera::cli {
namespace {

/// An argument as messages show it: at most 64 characters, then "..." and its length.
std::string shown(const std::string& s) {
  constexpr std::size_t kMax = 64;
  if (s.size() <= kMax) return s;
  return s.substr(0, kMax) + "... (" + std::to_string(s.size()) + " characters)";
}

template <class T>
T to_number(const std::string& flag, const std::string& text, T lo, T hi) {
  T v{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || v < lo || v > hi) {
    throw std::runtime_error(flag + ": \"" + shown(text) + "\" is not an integer in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "]");
  }
  return v;
}

/// Seconds in [0, 31536000] (a year), as tessera.time_limit.
double to_seconds(const std::string& flag, const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || !(v >= 0.0 && v <= 31536000.0))
    throw std::runtime_error(flag + ": \"" + text.substr(0, 40) + "\" is not a number of seconds in [0, 31536000]");
  return v;
}

/// A finite number (--time), as the adapter's time argument.
double to_finite(const std::string& flag, const std::string& text) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || !std::isfinite(v))
    throw std::runtime_error(flag + ": \"" + text.substr(0, 40) + "\" is not a finite number");
  return v;
}

}  // namespace

const char* usage() {
  return "usage: tessera-render SCENE.yaml [--render NAME] [-o OUT] [--spp N]\n"
         "                      [--width W --height H] [--tile N | --scanline] [--threads N]\n"
         "                      [--seed N] [--step N] [--time T] [--time-limit SECONDS] [--device D]\n"
         "                      [--stats FILE.json]"
         "                      [--denoise | --no-denoise] [--progress | --quiet] [--check]\n"
         "\n"
         "Renders every entry of `renders:` in SCENE.yaml (or only --render NAME) from the\n"
         "raw volume named by its `volume:` block. Flags override the YAML.\n"
         "\n"
         "  --render NAME      render only this entry\n"
         "  -o OUT             write OUT.exr / OUT.png per output.formats (OUT.exr or OUT.png:\n"
         "                     that format only); with several renders, OUT_NAME.*\n"
         "  --spp N            samples per pixel (1..1048576)\n"
         "  --width W          image width in pixels (1..16384)\n"
         "  --height H         image height in pixels (1..16384)\n"
         "  --tile N           tile edge in pixels (0 = scanline order)\n"
         "  --scanline         scanline order (same as --tile 0)\n"
         "  --threads N        worker threads (0 = all hardware threads)\n"
         "  --seed N           random seed\n"
         "  --step N           render as the adapter does at simulation step N: that step's\n"
         "                     random numbers, camera (moving orbit, keyframes) and {step}\n"
         "                     in output names (default 0)\n"
         "  --time T           the simulation time of that step: {time} in output names and\n"
         "                     annotation text (default 0)\n"
         "  --time-limit S     seconds each render may take (0 = none; default\n"
         "                     tessera.time_limit); past it: error, no output file\n"
         "  --device D         auto, cpu or cuda: where renders trace (overrides tessera.device;\n"
         "                     auto is the CPU: the volume is read into host memory)\n"
         "  --denoise          denoise the PNG with Open Image Denoise (image.denoise: true)\n"
         "  --no-denoise       do not denoise (image.denoise: false)\n"
         "  --stats FILE.json  write render statistics as JSON\n"
         "  --progress         show a progress bar (default when stderr is a terminal)\n"
         "  --quiet            print nothing but errors\n"
         "  --check            check the scene and its volume file, render nothing\n"
         "  -h, --help         show this help\n"
         "  --version          show the version\n";
}

Args parse_args(int argc, const char* const* argv) {
  Args a;
  bool tile_given = false, scanline = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    std::optional<std::string> inline_value;
    if (arg.rfind("--", 0) == 0) {
      const auto eq = arg.find('=');
      if (eq != std::string::npos) {
        inline_value = arg.substr(eq + 1);
        arg.resize(eq);
      }
    }
    // The option's value: after '=' or the next argument
    const auto value = [&]() -> std::string {
      if (inline_value) return *inline_value;
      if (i + 1 >= argc) throw std::runtime_error(arg + " needs a value");
      return argv[++i];
    };
    const auto no_value = [&] {
      if (inline_value) throw std::runtime_error(arg + " takes no value");
    };

    if (arg == "-h" || arg == "--help") {
      no_value();
      a.help = true;
    } else if (arg == "--version") {
      no_value();
      a.version = true;
    } else if (arg == "--render") a.render = value();
    else if (arg == "-o" || arg == "--output") a.output = value();
    else if (arg == "--spp") a.spp = to_number<int>(arg, value(), 1, ImageDesc::kMaxSpp);
    else if (arg == "--width") a.width = to_number<int>(arg, value(), 1, ImageDesc::kMaxEdge);
    else if (arg == "--height") a.height = to_number<int>(arg, value(), 1, ImageDesc::kMaxEdge);
    else if (arg == "--tile") {
      a.tile = to_number<int>(arg, value(), 0, ImageDesc::kMaxEdge);
      tile_given = true;
    } else if (arg == "--scanline") {
      no_value();
      scanline = true;
      a.tile = 0;
    } else if (arg == "--threads") a.threads = to_number<int>(arg, value(), 0, 65536);
    else if (arg == "--seed")
      a.seed = to_number<std::uint64_t>(arg, value(), 0, std::numeric_limits<std::uint64_t>::max());
    else if (arg == "--step")
      a.step = to_number<std::int64_t>(arg, value(), std::numeric_limits<std::int64_t>::min(),
                                       std::numeric_limits<std::int64_t>::max());
    else if (arg == "--time") a.time = to_finite(arg, value());
    else if (arg == "--stats") a.stats = value();
    else if (arg == "--time-limit") a.time_limit = to_seconds(arg, value());
    else if (arg == "--device") {
      const std::string v = value();
      if (v == "auto") a.device = config::DeviceChoice::Auto;
      else if (v == "cpu") a.device = config::DeviceChoice::Cpu;
      else if (v == "cuda") a.device = config::DeviceChoice::Cuda;
      else throw std::runtime_error("--device: \"" + v.substr(0, 40) + "\" is not a device (allowed: auto, cpu, cuda)");
    } else if (arg == "--progress") {
      no_value();
      a.progress = true;
    } else if (arg == "--quiet" || arg == "-q") {
      no_value();
      a.quiet = true;
    } else if (arg == "--check") {
      no_value();
      a.check = true;
    } else if (arg == "--denoise" || arg == "--no-denoise") {
      no_value();
      if (a.denoise && *a.denoise != (arg == "--denoise"))
        throw std::runtime_error("--denoise and --no-denoise exclude each other");
      a.denoise = arg == "--denoise";
    } else if (arg.size() > 1 && arg[0] == '-')
      throw std::runtime_error("unknown option " + shown(arg) + " (see --help)");
    else if (a.scene.empty()) a.scene = arg;
    else throw std::runtime_error("unexpected argument \"" + shown(arg) + "\" (one SCENE.yaml only)");
  }
  if (a.help || a.version) return a;
  if (tile_given && scanline) throw std::runtime_error("--tile and --scanline exclude each other");
  if (a.progress && a.quiet) throw std::runtime_error("--progress and --quiet exclude each other");
  if (a.scene.empty())
    throw std::runtime_error("no scene file given (usage: tessera-render SCENE.yaml [options], see --help)");
  for (const auto* s : {&a.render, &a.output, &a.stats})
    if (*s && (*s)->empty()) throw std::runtime_error("empty value for an option");
  return a;
}

}  // namespace tessera::cli
