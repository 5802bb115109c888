#pragma once
// The background's lookups (Environment::sample, pdf, eval: lights/environment_eval.h, one
// definition for the host and the device) run on the GPU for given inputs, for a test that
// compares them with the host's (test_gpu_environment.cpp). A CUDA build's GPU tests only.
#include "lights/environment.h"
#include "sampling/distribution.h"

#include <algorithm>

#include <span>
#include <vector>

namespace gpu_test {

/// What one probe reads: sample(u1, u2) (its direction, pdf and radiance), then pdf and eval
/// of that direction, and eval of a given direction `look`.
struct EnvProbe {
  double u1 = 0.0, u2 = 0.0;
  tessera::Vec3 look{0.0};
  tessera::Vec3 d{0.0};
  double pdf = 0.0;
  tessera::Color sampled{0.0};
  double pdf_of_d = 0.0;
  tessera::Color eval_d{0.0};
  tessera::Color eval_look{0.0};
};

/// Fills the outputs of `p` from its inputs with `env` (host and device code).
TESSERA_HOST_DEVICE inline void run_probe(const tessera::Environment& env, EnvProbe& p) {
  p.sampled = env.sample(p.u1, p.u2, &p.d, &p.pdf);
  p.pdf_of_d = env.pdf(p.d);
  p.eval_d = env.eval(p.d);
  p.eval_look = env.eval(p.look);
}

/// A 1D distribution's sample of u: Distribution1DView::sample's bin, and the bin that
/// std::upper_bound over the same table gives (the library's algorithm in device code).
struct DistProbe {
  double u = 0.0;
  double x = 0.0;
  std::size_t bin = 0, bin_lib = 0;
};

TESSERA_HOST_DEVICE inline void run_probe(const tessera::Distribution1DView& d, DistProbe& p) {
  p.x = d.sample(p.u, &p.bin);
  p.bin_lib = static_cast<std::size_t>(std::upper_bound(d.cdf, d.cdf + d.n + 1, p.u) - d.cdf);
}

/// run_probe for every probe on the current CUDA device, over a device copy of `table`
/// (Distribution1D's layout: f, cdf, integral) for n bins.
std::vector<DistProbe> probe_distribution_on_device(std::span<const double> table, std::size_t n,
                                                    std::span<const DistProbe> in);

/// run_probe for every probe on the current CUDA device, over device copies of the envmap's
/// tables and of `env` (Environment::relocated, as the backend copies them). Throws
/// std::runtime_error naming a failed CUDA call.
std::vector<EnvProbe> probe_environment_on_device(const tessera::Environment& env, std::span<const EnvProbe> in);

}  // namespace gpu_test
