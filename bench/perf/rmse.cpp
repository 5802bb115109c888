/// tessera-rmse: error of rendered EXR images against a reference EXR (benchmark helper,
/// not a test). For every image it prints one CSV line
///
///   image,rmse_rgb,rmse_lum,rel_rmse_lum,mean_lum_ref,ref_var_lum,relmse_lum,ref_relvar_lum
///
/// rmse_rgb:     sqrt of the mean over pixels and R, G, B of (img - ref)^2 (linear radiance);
/// rmse_lum:     the same for luminance (0.2126 R + 0.7152 G + 0.0722 B);
/// rel_rmse_lum: rmse_lum / mean luminance of the reference;
/// ref_var_lum:  mean over pixels of the reference's `variance` channel (the variance of its
///               pixel means), 0 if absent: the reference's own noise. Since the reference and
///               the image are independent, rmse_lum^2 - ref_var_lum estimates the error of the
///               image against the exact answer.
///
///   tessera-rmse REF.exr IMG.exr [IMG.exr ...] [--header]
#include <tessera/image_io.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

struct Error {
  double rmse_rgb = 0, rmse_lum = 0, rel_rmse_lum = 0, mean_lum_ref = 0, ref_var_lum = 0;
  double relmse_lum = 0, ref_relvar_lum = 0;
};

Error compare(const tessera::Image& ref, const tessera::Image& img) {
  if (img.width != ref.width || img.height != ref.height)
    throw std::runtime_error("image is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                             ", reference is " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
  const std::size_t n = static_cast<std::size_t>(ref.width) * ref.height;
  constexpr double kRelEps = 0.01;
  double se_rgb = 0, se_lum = 0, sum_lum = 0, sum_var = 0, sum_rel = 0, sum_relvar = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* a = &img.rgba[i * 4];
    const float* b = &ref.rgba[i * 4];
    for (int c = 0; c < 3; ++c) se_rgb += (double(a[c]) - b[c]) * (double(a[c]) - b[c]);
    const double dl = luminance(a) - luminance(b);
    se_lum += dl * dl;
    const double lb = luminance(b);
    sum_lum += lb;
    sum_rel += dl * dl / (lb * lb + kRelEps);
    if (!ref.variance.empty()) {
      sum_var += ref.variance[i];
      sum_relvar += ref.variance[i] / (lb * lb + kRelEps);
    }
  }
  Error e;
  e.rmse_rgb = std::sqrt(se_rgb / (3.0 * n));
  e.rmse_lum = std::sqrt(se_lum / n);
  e.mean_lum_ref = sum_lum / n;
  e.rel_rmse_lum = e.mean_lum_ref > 0 ? e.rmse_lum / e.mean_lum_ref : 0.0;
  e.ref_var_lum = sum_var / n;
  e.relmse_lum = sum_rel / n;
  e.ref_relvar_lum = sum_relvar / n;
  return e;
}

}  // namespace

int main(int argc, char** argv) try {
  std::vector<std::string> files;
  bool header = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--header") header = true;
    else files.push_back(a);
  }
  if (files.size() < 2) {
    std::fprintf(stderr, "usage: tessera-rmse REF.exr IMG.exr [IMG.exr ...] [--header]\n");
    return 2;
  }
  const tessera::Image ref = tessera::read_exr(files[0]);
  if (header) std::printf("image,rmse_rgb,rmse_lum,rel_rmse_lum,mean_lum_ref,ref_var_lum,relmse_lum,ref_relvar_lum\n");
  for (std::size_t k = 1; k < files.size(); ++k) {
    const Error e = compare(ref, tessera::read_exr(files[k]));
    std::printf("%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", files[k].c_str(), e.rmse_rgb, e.rmse_lum, e.rel_rmse_lum,
                e.mean_lum_ref, e.ref_var_lum, e.relmse_lum, e.ref_relvar_lum);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "tessera-rmse: error: %s\n", e.what());
  return 1;
}
