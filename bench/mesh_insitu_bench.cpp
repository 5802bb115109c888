// One adapter call over an unstructured hex mesh, per call, as a simulation with a fixed mesh
// sees it: the values change every step; the geometry is the same (found by its hash, no
// promise), promised the same (tessera_mesh_unchanged), or moved a little every step (the
// layout built and every element checked at every call: what an unchanged mesh cost before
// the hash). Not a test: prints seconds per call (median of the steps after the first) and
// writes a CSV.
//
//   mesh_insitu_bench [--cells N] [--steps S] [--csv PATH] [--threads T] [--only moved|same|promised]
//                     [--device auto|cpu|cuda]
//   (defaults: 64, 6, mesh_insitu_bench.csv, 0 = all hardware threads, every mode, auto)
// Also per call: the bytes copied to the device and to the host (a GPU render's copies; the
// mesh's host arrays are the simulation's, so `auto` renders on the CPU: pass --device cuda).
#include <tessera/adapter.h>

#include "mesh_call_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

struct Row {
  std::string mode;
  double call_s = 0.0, prepare_s = 0.0, to_device_mb = 0.0, to_host_mb = 0.0;
  int reused = 0;
};

}  // namespace

int main(int argc, char** argv) {
  tessera::bench::MeshCallArgs args;
  args.csv = "mesh_insitu_bench.csv";
  if (const std::string bad = tessera::bench::parse_mesh_call_args(argc, argv, args); !bad.empty()) {
    std::fprintf(stderr, "mesh_insitu_bench: unknown flag %s\n", bad.c_str());
    return 2;
  }
  const std::int64_t cells = args.cells;
  const int steps = args.steps;
  const std::string csv = args.csv;
  const fs::path dir = fs::temp_directory_path() / ("mesh_insitu_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path config = dir / "bench.yaml";
  std::ofstream(config) << tessera::bench::mesh_call_config((dir / "out").string(), args.threads, args.device);
  const std::int64_t n[3] = {cells + 1, cells + 1, cells + 1};
  std::vector<Row> rows;
  std::string device;  // where the renders ran
  for (const std::string& mode : tessera::bench::mesh_call_modes(args)) {
    tessera_test::MeshBlock block(n, 0, cells);
    std::vector<tessera_mesh_domain> domains = {block.domain(tessera_test::MeshBlock::Form::Hexes)};
    tessera::insitu::Adapter ad;
    ad.set_quiet(true);
    if (ad.open(config.string()) != TESSERA_OK) {
      std::fprintf(stderr, "mesh_insitu_bench: %s\n", ad.last_error().c_str());
      return 1;
    }
    std::vector<double> call, prepare, to_device, to_host;
    Row row{mode};
    for (int s = 1; s <= steps; ++s) {
      tessera::bench::mesh_call_step(mode, s, block, ad);
      const auto t0 = std::chrono::steady_clock::now();
      if (ad.execute_mesh_domains(s, 0.1 * s, domains) != TESSERA_OK) {
        std::fprintf(stderr, "mesh_insitu_bench: %s\n", ad.last_error().c_str());
        return 1;
      }
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (s == 1) continue;
      call.push_back(t);
      const tessera::insitu::RenderResult& r = ad.last_results().at(0);
      prepare.push_back(r.prepare_seconds);
      to_device.push_back(static_cast<double>(r.stats.bytes_to_device) * 1e-6);
      to_host.push_back(static_cast<double>(r.stats.bytes_to_host) * 1e-6);
      row.reused += r.mesh_layout_reused ? 1 : 0;
      if (device.empty()) device = r.device;
    }
    row.call_s = tessera::bench::median(call);
    row.prepare_s = tessera::bench::median(prepare);
    row.to_device_mb = tessera::bench::median(to_device);
    row.to_host_mb = tessera::bench::median(to_host);
    rows.push_back(row);
  }
  fs::remove_all(dir);
  const double mel = static_cast<double>(cells * cells * cells) * 1e-6;
  std::printf("%lld^3 hexes, 32x32, 1 spp, steps 2..%d, on %s\n", static_cast<long long>(cells), steps, device.c_str());
  std::printf("%-12s %10s %12s %12s %8s %12s %12s\n", "geometry", "call_s", "call_s/Mel", "prepare_s", "reused",
              "to_device_MB", "to_host_MB");
  std::ofstream out(csv);
  out << "geometry,cells,steps,device,call_s,call_s_per_million,prepare_s,layout_reused_calls,to_device_mb,"
         "to_host_mb\n";
  for (const Row& r : rows) {
    std::printf("%-12s %10.4f %12.4f %12.4f %5d/%d %12.3f %12.3f\n", r.mode.c_str(), r.call_s, r.call_s / mel,
                r.prepare_s, r.reused, steps - 1, r.to_device_mb, r.to_host_mb);
    out << '"' << r.mode << "\"," << cells * cells * cells << ',' << steps << ",\"" << device << "\"," << r.call_s
        << ',' << r.call_s / mel << ',' << r.prepare_s << ',' << r.reused << ',' << r.to_device_mb << ','
        << r.to_host_mb << '\n';
  }
  std::printf("wrote %s\n", csv.c_str());
  return 0;
}
