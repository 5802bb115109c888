// Cost of an execute call where no trigger fires: what instrumenting a simulation costs on the
// steps that render nothing (target: under a microsecond). Not a test: prints ns per call and
// writes a CSV.
//
//   insitu_noop_execute [CSV_PATH] [CALLS]     (defaults: insitu_noop_execute.csv, 5000000)
#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// A config with `renders` renders whose triggers never fire at odd steps >= 1.
std::string write_config(const fs::path& dir, int renders, const char* trigger) {
  std::string yaml = "tessera:\n  output_dir: " + (dir / "out").string() + "\nrenders:\n";
  for (int r = 0; r < renders; ++r)
    yaml += "  - name: r" + std::to_string(r) + "\n    field: density\n    trigger: " + trigger +
            "\n    camera: {position: [2, 2, 2]}\n    transfer_function: {opacity: [[0, 0], [1, 1]]}\n";
  const fs::path path = dir / ("bench_" + std::to_string(renders) + ".yaml");
  std::ofstream(path) << yaml;
  return path.string();
}

struct Row {
  std::string api, trigger;
  int renders;
  long long calls;
  double ns_per_call;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string csv_path = argc > 1 ? argv[1] : "insitu_noop_execute.csv";
  const long long calls = argc > 2 ? std::atoll(argv[2]) : 5000000LL;
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("tessera_bench_" + std::to_string(rd()));
  fs::create_directories(dir);

  // A field the calls never read: 64^3 float32
  constexpr int n = 64;
  std::vector<float> data(static_cast<std::size_t>(n) * n * n, 1.0f);
  tessera_field field{};
  field.name = "density";
  field.data = data.data();
  field.dtype = TESSERA_FLOAT32;
  for (int a = 0; a < 3; ++a) field.dims[a] = n;
  field.byte_strides[0] = 4;
  field.byte_strides[1] = 4 * n;
  field.byte_strides[2] = 4 * n * n;
  tessera_grid grid{};
  for (int a = 0; a < 3; ++a) {
    grid.spacing[a] = 1.0 / (n - 1);
    grid.global_dims[a] = n;
  }

  std::vector<Row> rows;
  const char* triggers[] = {"{every: 2}", "{at: [0, 100, 200, 400, 800]}"};
  for (const char* trigger : triggers)
    for (const int renders : {1, 8}) {
      const std::string cfg = write_config(dir, renders, trigger);
      // C API
      tessera_adapter* a = nullptr;
      if (tessera_open(cfg.c_str(), -1, &a) != TESSERA_OK) {
        std::fprintf(stderr, "open failed: %s\n", tessera_last_error(nullptr));
        return 1;
      }
      int failures = 0;
      auto t0 = std::chrono::steady_clock::now();
      for (long long i = 0; i < calls; ++i)
        failures += tessera_execute(a, 2 * i + 1, 0.0, &grid, &field, 1) != TESSERA_OK;
      double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      tessera_close(a);
      rows.push_back({"c", trigger, renders, calls, 1e9 * s / calls});

      // C++ API
      tessera::insitu::Adapter adapter;
      adapter.open(cfg);
      t0 = std::chrono::steady_clock::now();
      for (long long i = 0; i < calls; ++i)
        failures += adapter.execute(2 * i + 1, 0.0, grid, {&field, 1}) != TESSERA_OK;
      s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      rows.push_back({"c++", trigger, renders, calls, 1e9 * s / calls});
      if (failures) std::fprintf(stderr, "%d calls failed\n", failures);
    }

  std::ofstream csv(csv_path);
  csv << "api,trigger,renders,calls,ns_per_call\n";
  std::printf("%-4s %-32s %8s %10s %12s\n", "api", "trigger", "renders", "calls", "ns/call");
  for (const Row& r : rows) {
    std::printf("%-4s %-32s %8d %10lld %12.2f\n", r.api.c_str(), r.trigger.c_str(), r.renders, r.calls, r.ns_per_call);
    csv << r.api << ",\"" << r.trigger << "\"," << r.renders << "," << r.calls << "," << r.ns_per_call << "\n";
  }
  std::printf("wrote %s\n", csv_path.c_str());
  std::error_code ec;
  fs::remove_all(dir, ec);
  return 0;
}
