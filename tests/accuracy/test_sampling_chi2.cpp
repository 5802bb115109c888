// Sampling correctness: every directional sampler's histogram matches its own evaluated pdf
// (docs/accuracy.md, "Sampling: chi-square").
//
// For each sampler, directions are drawn with sample() and binned on the sphere; the expected
// probability of each bin is the integral of the sampler's pdf() (the density the estimator
// divides by and weights MIS with) over the bin, by a sub x sub midpoint rule in (theta, phi),
// theta = angle to the binning axis (weight sin theta). Two extra bins hold directions below mu_min (expected: the
// pdf's integral there) and failed samples (expected: 1 - integral of the pdf over the
// sphere). Pearson's chi-square (bins with expected count < 5 merged into the next) must stay
// below the critical value at significance 1e-4. Each sample's returned pdf must also equal
// pdf() at its direction (relative 1e-9; 1e-6 for the envmap, whose pdf() recomputes the
// angle through acos). Fixed seeds.
//
// Samplers: HG phase (hg_sample vs hg_eval, g from -0.9 to 0.95), the GGX + Lambert surface
// BRDF (SurfaceBrdf::sample vs ::pdf), rect and sphere lights (sample() vs the solid-angle
// pdf() of the direction, 0 where the direction misses the light), the environment map
// (Environment::sample vs ::pdf on a small synthetic Image).
#include <catch2/catch.hpp>

#include "accuracy_support.h"
#include "kernel/phase_hg.h"
#include "kernel/surface_brdf.h"
#include "lights/area_lights.h"
#include "lights/environment.h"
#include "sampling/rng.h"

#include <functional>
#include <memory>

using namespace tessera_acc;
using tessera::Frame;

namespace {

constexpr double kAlpha = 1e-4;

/// Bins over the sphere about `axis`: mu in [mu_edges.front(), 1] cut at mu_edges, phi in
/// n_phi equal parts; then the bin "mu below mu_min" and the bin "failed".
struct SphereBins {
  Frame frame;
  std::vector<double> mu_edges;
  int n_phi;

  SphereBins(const Vec3& axis, std::vector<double> edges, int nphi)
      : frame(glm::normalize(axis)), mu_edges(std::move(edges)), n_phi(nphi) {}
  /// Equal steps in mu over [mu_min, 1].
  static std::vector<double> uniform(double mu_min, int n) {
    std::vector<double> e(n + 1);
    for (int i = 0; i <= n; ++i) e[i] = mu_min + (1.0 - mu_min) * i / n;
    e[n] = 1.0;
    return e;
  }
  /// Steps in mu growing quadratically away from mu = 1: fine bins around the axis.
  static std::vector<double> clustered(double mu_min, int n) {
    std::vector<double> e(n + 1);
    for (int i = 0; i <= n; ++i) {
      const double s = static_cast<double>(n - i) / n;
      e[i] = 1.0 - (1.0 - mu_min) * s * s;
    }
    e[n] = 1.0;
    return e;
  }
  int n_mu() const { return static_cast<int>(mu_edges.size()) - 1; }
  int count() const { return 2 + n_mu() * n_phi; }
  int below() const { return 0; }
  int failed() const { return count() - 1; }
  int bin(const Vec3& w) const {
    const Vec3 l = frame.to_local(w);
    const double mu = std::clamp(l.z, -1.0, 1.0);
    if (mu < mu_edges.front()) return below();
    const int im = std::min(
        n_mu() - 1, static_cast<int>(std::upper_bound(mu_edges.begin(), mu_edges.end(), mu) - mu_edges.begin()) - 1);
    double phi = std::atan2(l.y, l.x);
    if (phi < 0.0) phi += 2.0 * kPi;
    const int ip = std::min(n_phi - 1, static_cast<int>(phi / (2.0 * kPi) * n_phi));
    return 1 + im * n_phi + ip;
  }
  Vec3 dir(double mu, double phi) const {
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return frame.to_world(Vec3(s * std::cos(phi), s * std::sin(phi), mu));
  }
  /// Integral of pdf over mu in [mu0, mu1], phi in [phi0, phi1]: m x m midpoint rule in
  /// (theta, phi) with the weight sin(theta) (exact for the envmap's pdf ~ 1 / sin(theta)).
  double cell(const std::function<double(const Vec3&)>& pdf, double mu0, double mu1, double phi0, double phi1,
              int m) const {
    double s = 0.0;
    const double th0 = std::acos(std::clamp(mu1, -1.0, 1.0)), th1 = std::acos(std::clamp(mu0, -1.0, 1.0));
    const double dt = (th1 - th0) / m, dp = (phi1 - phi0) / m;
    for (int i = 0; i < m; ++i) {
      const double th = th0 + (i + 0.5) * dt;
      for (int j = 0; j < m; ++j) s += pdf(dir(std::cos(th), phi0 + (j + 0.5) * dp)) * std::sin(th);
    }
    return s * dt * dp;
  }
  std::vector<double> probabilities(const std::function<double(const Vec3&)>& pdf, int sub) const {
    std::vector<double> p(count(), 0.0);
    const double dphi = 2.0 * kPi / n_phi;
    double total = 0.0;
    for (int im = 0; im < n_mu(); ++im)
      for (int ip = 0; ip < n_phi; ++ip) {
        const double v = cell(pdf, mu_edges[im], mu_edges[im + 1], ip * dphi, (ip + 1) * dphi, sub);
        p[1 + im * n_phi + ip] = v;
        total += v;
      }
    if (mu_edges.front() > -1.0) {
      for (int ip = 0; ip < n_phi; ++ip)
        p[below()] += cell(pdf, -1.0, mu_edges.front(), ip * dphi, (ip + 1) * dphi, 2 * sub);
      total += p[below()];
    }
    p[failed()] = std::max(0.0, 1.0 - total);
    return p;
  }
};

struct Chi2Result {
  double chi2 = 0.0, crit = 0.0;
  int dof = 0;
  double pdf_integral = 0.0;
  double worst_pdf = 0.0;  ///< max relative |returned pdf / pdf(wi) - 1|
  double failed_fraction = 0.0;
  std::string describe() const {
    std::ostringstream s;
    s << "chi2 " << chi2 << " on " << dof << " dof (critical " << crit << "), integral of pdf " << pdf_integral
      << ", failed fraction " << failed_fraction << ", worst pdf mismatch " << worst_pdf;
    return s.str();
  }
};

/// `draw(rng, &w, &pdf)` returns false on a failed sample.
Chi2Result run_chi2(const SphereBins& bins, const std::function<double(const Vec3&)>& pdf,
                    const std::function<bool(tessera::Rng&, Vec3*, double*)>& draw, int samples, std::uint64_t seed,
                    int sub) {
  std::vector<double> counts(bins.count(), 0.0);
  tessera::Rng rng(seed, 0, 0, 0);
  Chi2Result r;
  int failed = 0;
  for (int i = 0; i < samples; ++i) {
    Vec3 w;
    double p;
    if (!draw(rng, &w, &p)) {
      counts[bins.failed()] += 1.0;
      ++failed;
      continue;
    }
    counts[bins.bin(w)] += 1.0;
    const double q = pdf(w);
    r.worst_pdf = std::max(r.worst_pdf, q > 0.0 ? std::fabs(p / q - 1.0) : INFINITY);
  }
  const std::vector<double> prob = bins.probabilities(pdf, sub);
  for (int i = 0; i < bins.count(); ++i)
    if (i != bins.failed()) r.pdf_integral += prob[i];
  r.chi2 = chi_square(counts, prob, samples, &r.dof);
  r.crit = chi2_critical(r.dof, kAlpha);
  r.failed_fraction = static_cast<double>(failed) / samples;
  return r;
}

}  // namespace

TEST_CASE("HG sampling: histogram of directions equals hg_eval, g from -0.9 to 0.95", "[accuracy][chi2]") {
  tessera::Rng pick(11, 0, 0, 0);
  for (const double g : {-0.9, -0.5, 0.0, 0.3, 0.7, 0.95}) {
    const Vec3 d_in = glm::normalize(Vec3(pick.uniform() - 0.5, pick.uniform() - 0.5, pick.uniform() - 0.5));
    auto pdf = [&](const Vec3& w) { return tessera::hg_eval(glm::dot(d_in, w), g); };
    auto draw = [&](tessera::Rng& rng, Vec3* w, double* p) {
      const double u1 = rng.uniform(), u2 = rng.uniform();
      *p = tessera::hg_sample(d_in, g, u1, u2, w);
      return true;
    };
    // Fine bins about the lobe's axis, and uniform bins about an unrelated axis.
    const double pole = g >= 0.0 ? 1.0 : -1.0;
    const SphereBins about_lobe(pole * d_in, SphereBins::clustered(-1.0, 40), 24);
    const SphereBins about_other(Vec3(1.0, 2.0, 3.0), SphereBins::uniform(-1.0, 24), 32);
    for (const SphereBins* b : {&about_lobe, &about_other}) {
      const Chi2Result r = run_chi2(*b, pdf, draw, 1000000, 100 + static_cast<int>(g * 100), 16);
      INFO("g " << g << (b == &about_lobe ? ", bins about the lobe: " : ", bins about (1,2,3): ") << r.describe());
      CHECK(r.chi2 < r.crit);
      CHECK(r.pdf_integral == Approx(1.0).epsilon(2e-3));
      CHECK(r.worst_pdf < 1e-9);
    }
  }
}

TEST_CASE("GGX + Lambert BRDF sampling: histogram of wi equals SurfaceBrdf::pdf", "[accuracy][chi2]") {
  struct Case {
    const char* name;
    double albedo, f0, roughness, cos_o;
    bool about_mirror;  ///< bin about the mirror direction (sharp lobes) instead of the normal
  };
  const Case cases[] = {
      {"Lambert only", 0.7, 0.0, 0.5, 0.6, false},
      {"dielectric-like, mostly diffuse", 0.5, 0.04, 0.5, 0.8, false},
      {"metal-like mixture", 0.3, 0.8, 0.3, 0.5, false},
      {"specular only", 0.0, 0.9, 0.4, 0.7, false},
      {"grazing view", 0.2, 0.5, 0.6, 0.1, false},
      {"sharp lobe (alpha 0.0225)", 0.1, 0.9, 0.15, 0.7, true},
  };
  const Vec3 n = glm::normalize(Vec3(0.2, -0.4, 0.9));
  const Frame fn(n);
  int k = 0;
  for (const Case& c : cases) {
    const double sin_o = std::sqrt(1.0 - c.cos_o * c.cos_o);
    const Vec3 wo = fn.to_world(Vec3(sin_o * std::cos(0.7 * k), sin_o * std::sin(0.7 * k), c.cos_o));
    const tessera::SurfaceBrdf brdf(n, Color(c.albedo), Color(c.f0), c.roughness);
    auto pdf = [&](const Vec3& w) { return brdf.pdf(wo, w); };
    auto draw = [&](tessera::Rng& rng, Vec3* w, double* p) {
      const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
      if (!brdf.sample(wo, u0, u1, u2, w)) return false;
      *p = brdf.pdf(wo, *w);  // the estimator's pdf for the sampled direction
      return *p > 0.0;
    };
    const Vec3 mirror = 2.0 * glm::dot(wo, n) * n - wo;
    const SphereBins bins = c.about_mirror ? SphereBins(mirror, SphereBins::clustered(-1.0, 48), 32)
                                           : SphereBins(n, SphereBins::uniform(0.0, 32), 48);
    const Chi2Result r = run_chi2(bins, pdf, draw, 2000000, 200 + k, c.about_mirror ? 32 : 16);
    INFO(c.name << ": p_spec " << brdf.p_spec << ", " << r.describe());
    CHECK(r.chi2 < r.crit);
    // Sampled and evaluated densities are the same function: the pdf integrates to the
    // fraction of samples that do not fail (checked bin-wise by chi-square, overall here).
    CHECK(std::fabs(r.pdf_integral - (1.0 - r.failed_fraction)) < 4.0 * std::sqrt(r.failed_fraction / 2e6) + 2e-3);
    ++k;
  }
}

TEST_CASE("rect light sampling: histogram of directions equals the solid-angle pdf", "[accuracy][chi2]") {
  const tessera::RectLightDesc d{Vec3(0.3, -0.2, 1.0), Vec3(0.1, 0.4, -1.0), 1.2, 0.5, Color(1.0)};
  const tessera::RectLight light(d);
  const Vec3 n = glm::normalize(d.target - d.position);
  const tessera::Frame lf(n);
  // Close and off-centre, far, and grazing (nearly in the light's plane).
  const Vec3 points[] = {d.position + 0.3 * n + 0.2 * lf.s, d.position + 4.0 * n - 1.5 * lf.t,
                         d.position + 0.15 * n + 2.5 * lf.s};
  int k = 0;
  for (const Vec3& x : points) {
    auto pdf = [&](const Vec3& w) {
      const double t = light.intersect_front(Ray{x, w});
      return t > 0.0 ? light.pdf(x, w, t) : 0.0;
    };
    auto draw = [&](tessera::Rng& rng, Vec3* w, double* p) {
      const tessera::LightSample s = light.sample(x, rng.uniform(), rng.uniform());
      *w = s.wi;
      *p = s.pdf;
      return s.pdf > 0.0;
    };
    // Bins about the direction to the centre, over the cone that holds the whole light.
    const Vec3 axis = glm::normalize(d.position - x);
    double mu_min = 1.0;
    for (const double su : {-1.0, 1.0})
      for (const double sv : {-1.0, 1.0}) {
        // Corners in any in-plane frame: the cone only needs to contain the rectangle.
        const Vec3 c = d.position + su * 0.5 * std::hypot(d.width, d.height) * lf.s +
                       sv * 0.5 * std::hypot(d.width, d.height) * lf.t;
        mu_min = std::min(mu_min, glm::dot(glm::normalize(c - x), axis));
      }
    const SphereBins bins(axis, SphereBins::uniform(std::max(-1.0, mu_min - 0.01), 24), 32);
    const Chi2Result r = run_chi2(bins, pdf, draw, 1000000, 300 + k, 96);
    INFO("point " << k << ": " << r.describe());
    CHECK(r.chi2 < r.crit);
    CHECK(r.pdf_integral == Approx(1.0).epsilon(3e-3));
    CHECK(r.failed_fraction == 0.0);
    CHECK(r.worst_pdf < 1e-9);
    ++k;
  }
}

TEST_CASE("sphere light sampling: histogram of directions equals the cone pdf", "[accuracy][chi2]") {
  const tessera::SphereLightDesc d{Vec3(0.5, 1.0, -0.5), 0.4, Color(1.0)};
  const tessera::SphereLight light(d);
  int k = 0;
  for (const double dist : {0.42, 1.5, 40.0}) {
    const Vec3 x = d.center + dist * glm::normalize(Vec3(0.3, -0.8, 0.5));
    auto pdf = [&](const Vec3& w) {
      const double t = light.intersect_front(Ray{x, w});
      return t > 0.0 ? light.pdf(x, w, t) : 0.0;
    };
    auto draw = [&](tessera::Rng& rng, Vec3* w, double* p) {
      const tessera::LightSample s = light.sample(x, rng.uniform(), rng.uniform());
      *w = s.wi;
      *p = s.pdf;
      return s.pdf > 0.0;
    };
    const double sin2 = (d.radius / dist) * (d.radius / dist);
    const double cos_max = std::sqrt(1.0 - sin2);
    const Vec3 axis = glm::normalize(d.center - x);
    const SphereBins bins(axis, SphereBins::uniform(cos_max - 1e-9 * (1.0 - cos_max), 20), 24);
    const Chi2Result r = run_chi2(bins, pdf, draw, 1000000, 400 + k, 8);
    INFO("distance " << dist << " (radius 0.4): " << r.describe());
    CHECK(r.chi2 < r.crit);
    CHECK(r.pdf_integral == Approx(1.0).epsilon(1e-3));
    CHECK(r.failed_fraction == 0.0);
    // From just outside, grazing directions may miss the sphere by rounding; pdf() then
    // reads 0 for them (the sample keeps the tangent distance).
    CHECK(r.worst_pdf < (dist < 0.5 ? INFINITY : 1e-9));
    ++k;
  }
}

TEST_CASE("envmap importance sampling: histogram of directions equals Environment::pdf", "[accuracy][chi2]") {
  // 16 x 8 texels: a smooth gradient, a bright texel, a black band (never sampled) and a
  // black texel at the bottom pole row.
  constexpr int W = 16, H = 8;
  auto img = std::make_shared<tessera::Image>();
  img->width = W;
  img->height = H;
  img->rgba.assign(W * H * 4, 1.0f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      float* p = img->px(x, y);
      const float v = 0.2f + 0.1f * x + 0.05f * y;
      p[0] = v;
      p[1] = 0.5f * v;
      p[2] = (x % 3 == 0) ? 1.5f * v : 0.3f;
      if (x >= 5 && x <= 6) p[0] = p[1] = p[2] = 0.0f;  // black band
    }
  img->px(11, 2)[0] = 40.0f;  // a sun
  img->px(3, H - 1)[0] = img->px(3, H - 1)[1] = img->px(3, H - 1)[2] = 0.0f;
  tessera::BackgroundDesc bd;
  bd.type = tessera::BackgroundType::EnvMap;
  bd.envmap = img;
  bd.up = Vec3(0.3, -0.2, 1.0);
  bd.intensity = 2.0;
  const tessera::Environment env(bd);
  auto pdf = [&](const Vec3& w) { return env.pdf(w); };
  int black_hits = 0;
  auto draw = [&](tessera::Rng& rng, Vec3* w, double* p) {
    const Color L = env.sample(rng.uniform(), rng.uniform(), w, p);
    if (tessera::is_black(L)) ++black_hits;
    return *p > 0.0;
  };
  SECTION("bins aligned with the texels (2 x 2 per texel) in the envmap frame") {
    // In the frame of `up`, mu = cos(theta); edges at the texel rows' cos(theta).
    std::vector<double> edges;
    for (int i = 2 * H; i >= 0; --i) edges.push_back(std::cos(kPi * i / (2 * H)));
    edges.front() = -1.0;
    edges.back() = 1.0;
    const SphereBins bins(bd.up, edges, 2 * W);
    const Chi2Result r = run_chi2(bins, pdf, draw, 2000000, 501, 8);
    INFO(r.describe() << ", samples on black texels " << black_hits);
    CHECK(r.chi2 < r.crit);
    CHECK(r.pdf_integral == Approx(1.0).epsilon(1e-6));
    CHECK(r.failed_fraction == 0.0);
    CHECK(r.worst_pdf < 1e-6);
    CHECK(black_hits == 0);
  }
  SECTION("uniform bins about an unrelated axis") {
    const SphereBins bins(Vec3(1.0, 0.5, -0.2), SphereBins::uniform(-1.0, 24), 48);
    // The pdf jumps at texel edges (40x at the sun): a fine rule keeps the expected counts
    // of the cut bins accurate.
    const Chi2Result r = run_chi2(bins, pdf, draw, 2000000, 502, 64);
    INFO(r.describe());
    CHECK(r.chi2 < r.crit);
    CHECK(r.pdf_integral == Approx(1.0).epsilon(2e-3));
    CHECK(r.worst_pdf < 1e-6);
  }
}
