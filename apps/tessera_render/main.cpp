// tessera-render: render the scenes of a YAML file from a raw volume (docs/cli.md).
// Every failure ends as one line `tessera-render: error: ...` on stderr and exit status 1.
#include "parse_args.h"

#include <tessera/config/config.h>
#include <tessera/config/raw_volume.h>
#include <tessera/denoiser.h>
#include <tessera/job/output_files.h>
#include <tessera/job/render_job.h>
#include <tessera/job/stats_json.h>

#include <tessera/message_text.h>

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace tessera::cli {

using namespace tessera::job;  // the render job this program runs

namespace {

/// The renders the command line asks for, in config order.
std::vector<const config::RenderSpec*> select_renders(const config::Config& cfg, const Args& args) {
  std::vector<const config::RenderSpec*> out;
  if (!args.render) {
    for (const auto& r : cfg.renders) out.push_back(&r);
    return out;
  }
  if (const auto* r = cfg.find_render(*args.render)) return {r};
  std::string names;
  for (const auto& r : cfg.renders) names += (names.empty() ? "" : ", ") + r.name;
  throw std::runtime_error("--render " + *args.render + ": no such render in " + cfg.path + " (renders: " + names +
                           ")");
}

int run(int argc, const char* const* argv) {
  const Args args = parse_args(argc, argv);
  if (args.help) {
    std::fputs(usage(), stdout);
    return 0;
  }
  if (args.version) {
    std::puts("tessera-render 0.1.0");
    return 0;
  }

  // Config, selection and volume, all checked before the first render
  const config::Config cfg = config::load_config(args.scene);
  if (!cfg.volume) {
    throw std::runtime_error(args.scene + ": no volume: block (tessera-render needs one: file, "
                                          "dims, dtype, ...)");
  }
  const auto renders = select_renders(cfg, args);
  const bool several = renders.size() > 1;
  std::vector<std::vector<OutputTarget>> targets;
  for (const auto* r : renders)
    targets.push_back(output_targets(cfg.global, *r, args.output, several, args.step, args.time));
  // image.denoise: the library is found (or the run fails) before anything is read or rendered
  for (const auto* r : renders) {
    if (!args.denoise.value_or(r->image.denoise)) continue;
    try {
      require_denoiser();
    } catch (const DenoiserUnavailable& e) {
      throw std::runtime_error(cfg.path + ": render '" + r->name + "': image.denoise: " + e.what());
    }
    break;
  }

  check_volume_memory(cfg);  // before a byte of the file is read
  const config::RawVolume volume = config::load_raw_volume(*cfg.volume);
  VolumeInfo info =
      describe_volume(volume, *cfg.volume, renders.empty() ? IntegratorDesc{} : renders.front()->integrator.desc);
  if (args.check) {  // --check: scene, selection, output paths and volume are valid
    for (const std::string& w : info.warnings) std::fprintf(stderr, "tessera-render: warning: %s\n", w.c_str());
    if (!args.quiet) std::printf("%s: ok (%zu render%s)\n", args.scene.c_str(), renders.size(), several ? "s" : "");
    return 0;
  }

  // Render each, reporting as we go
  const bool show_progress = !args.quiet && (args.progress || isatty(STDERR_FILENO));
  std::vector<RenderRecord> records;
  for (std::size_t i = 0; i < renders.size(); ++i) {
    RenderRecord rec = run_render(cfg, *renders[i], info, args, targets[i], show_progress);
    if (!args.quiet) {
      const double secs = rec.stats.wall_seconds;
      std::printf("%s: %dx%d, %d spp, %.3f s (%.3g samples/s) ->", rec.name.c_str(), rec.width, rec.height, rec.spp,
                  secs, secs > 0 ? double(rec.stats.samples) / secs : 0.0);
      for (const auto& o : rec.outputs) std::printf(" %s", o.c_str());
      std::printf("\n");
      std::fflush(stdout);
    }
    // Warnings go to stderr even with --quiet: they say the image may be wrong
    for (const std::string& w : rec.warnings)
      std::fprintf(stderr, "tessera-render: warning: %s: %s\n", rec.name.c_str(), w.c_str());
    records.push_back(std::move(rec));
  }
  if (args.stats) write_stats_json(*args.stats, records);
  return 0;
}

/// One line: newlines in the message become "; "; a long path is cut to its first and last
/// parts, and nothing prints raw (message_text.h).
void print_error(std::string message) {
  for (std::size_t p; (p = message.find('\n')) != std::string::npos;) message.replace(p, 1, "; ");
  message = message_quoting(std::move(message), {});
  std::fprintf(stderr, "tessera-render: error: %s\n", message.c_str());
}

}  // namespace
}  // namespace tessera::cli

int main(int argc, char** argv) {
  try {
    return tessera::cli::run(argc, argv);
  } catch (const std::bad_alloc&) {
    tessera::cli::print_error("out of memory");
  } catch (const std::exception& e) {
    tessera::cli::print_error(e.what());
  } catch (...) {
    tessera::cli::print_error("unknown error");
  }
  return 1;
}
