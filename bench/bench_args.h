#pragma once
/// Command-line flags the render benchmarks share (mpi_render_bench, distributed_bench,
/// paged_field_bench): --csv FILE --grid N --image W H --spp S --reps R --threads T. Each
/// bench derives its Args from BenchArgs, sets its own defaults, and handles its other flags.
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tessera::bench {

struct BenchArgs {
  std::string csv;
  int grid = 96, width = 128, height = 128, spp = 8, reps = 3, threads = 1;
};

/// Parses argv into `a`. A flag that is not a shared one goes to extra(flag, next), where
/// next() returns the flag's next argument; extra returns false for a flag it does not know.
/// A missing value or an unknown flag prints a message and exits with status 2.
template <class Extra>
void parse_args(int argc, char** argv, BenchArgs& a, Extra&& extra) {
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    const auto next = [&]() -> const char* {
      if (i + 1 < argc) return argv[++i];
      std::fprintf(stderr, "%s needs a value\n", s.c_str());
      std::exit(2);
    };
    if (s == "--csv") a.csv = next();
    else if (s == "--grid") a.grid = std::atoi(next());
    else if (s == "--image") {
      a.width = std::atoi(next());
      a.height = std::atoi(next());
    } else if (s == "--spp") a.spp = std::atoi(next());
    else if (s == "--reps") a.reps = std::atoi(next());
    else if (s == "--threads") a.threads = std::atoi(next());
    else if (!extra(s, next)) {
      std::fprintf(stderr, "unknown argument %s\n", s.c_str());
      std::exit(2);
    }
  }
}

}  // namespace tessera::bench
