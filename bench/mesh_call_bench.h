#pragma once
/// What the two benchmarks of an adapter call over a fixed mesh share (mesh_insitu_bench on one
/// process, mesh_mpi_bench under mpirun): their flags, the render's YAML, each step's change to
/// the mesh for a mode ("moved", "same (hash)", "promised"), and the median.
#include <tessera/adapter.h>

#include "mesh_blocks.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace tessera::bench {

struct MeshCallArgs {
  std::int64_t cells = 64;  ///< cells per axis of the hex mesh
  int steps = 6;
  std::string csv;
  int threads = 0;              ///< tessera.threads
  std::string only;             ///< a mode's prefix, or every mode
  std::string device = "auto";  ///< tessera.device: auto, cpu or cuda
};

/// Parses `--cells N --steps S --csv PATH --threads T --only MODE --device auto|cpu|cuda` into
/// `a` (its defaults kept for flags not given; values clamped to sane ranges). Returns the
/// unknown flag (or the device flag with a value it does not take), or "".
inline std::string parse_mesh_call_args(int argc, char** argv, MeshCallArgs& a) {
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--cells") a.cells = std::clamp<std::int64_t>(std::atoll(argv[i + 1]), 2, 1024);
    else if (flag == "--steps") a.steps = std::clamp(std::atoi(argv[i + 1]), 2, 1000);
    else if (flag == "--csv") a.csv = argv[i + 1];
    else if (flag == "--threads") a.threads = std::max(0, std::atoi(argv[i + 1]));
    else if (flag == "--only") a.only = argv[i + 1];
    else if (flag == "--device") {
      a.device = argv[i + 1];
      if (a.device != "auto" && a.device != "cpu" && a.device != "cuda") return flag + " " + a.device;
    } else return flag;
  }
  return "";
}

/// The modes, in order, that `a.only` selects.
inline std::vector<std::string> mesh_call_modes(const MeshCallArgs& a) {
  std::vector<std::string> modes;
  for (const std::string mode : {"moved", "same (hash)", "promised"})
    if (a.only.empty() || mode.rfind(a.only, 0) == 0) modes.push_back(mode);
  return modes;
}

/// The benchmarks' config: one small render (32x32, 1 spp, so that the mesh's cost shows) on
/// `device` (tessera.device).
inline std::string mesh_call_config(const std::string& output_dir, int threads, const std::string& device) {
  return "tessera:\n  output_dir: " + output_dir + "\n  threads: " + std::to_string(threads) + "\n  device: " + device +
         "\nrenders:\n  - name: view\n    field: f\n"
         "    image: {width: 32, height: 32, spp: 1}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 25, distance: 3}}, look_at: "
         "center, up: [0, 0, 1], fov: 40}\n"
         "    transfer_function: {range: auto, density_scale: 40, opacity: [[0, 0], [1, 1]]}\n";
}

/// Step s's change for `mode`: new values every step; "moved" shifts every x by 1e-7;
/// "promised" calls mesh_unchanged() from the second step.
inline void mesh_call_step(const std::string& mode, int s, tessera_test::MeshBlock& block, insitu::Adapter& ad) {
  for (double& v : block.vertex_values) v = 0.98 * v + 0.01;
  if (mode == "moved")
    for (double& x : block.x) x += 1e-7;
  if (mode == "promised" && s > 1) ad.mesh_unchanged();
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace tessera::bench
