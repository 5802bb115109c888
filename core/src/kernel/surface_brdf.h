#pragma once
/// The surface (BRDF) model used at "surface" collisions: Lambert (albedo / pi) plus GGX
/// microfacet specular (alpha = roughness^2, clamped to >= 1e-3) with Schlick Fresnel on F0 and
/// the separable Smith G. Reflection only: wi below the shading normal gives zero.
/// Conventions: n faces wo; wo points back along the incoming path, wi toward the light.
/// eval() returns f * |n . wi| (the cosine factor included).
#include <tessera/math.h>

#include "sampling/warp.h"

namespace tessera {

struct SurfaceBrdf {
  Vec3 n;
  Color albedo;
  Color f0;
  double alpha;
  double p_spec;  ///< probability of sampling the specular lobe (0 when F0 is black)

  SurfaceBrdf() = default;
  TESSERA_HOST_DEVICE SurfaceBrdf(const Vec3& normal, const Color& a, const Color& f, double roughness)
      : n(normal), albedo(a), f0(f) {
    alpha = std::fmax(1e-3, roughness * roughness);
    const double ms = max_component(f0), md = max_component(albedo);
    p_spec = ms > 0.0 ? std::clamp(ms / (ms + md), 0.1, 0.9) : 0.0;
    if (md <= 0.0 && ms > 0.0) p_spec = 1.0;
  }

  TESSERA_HOST_DEVICE double ggx_d(double cos_h) const {
    const double a2 = alpha * alpha;
    const double c2 = cos_h * cos_h;
    const double d = c2 * (a2 - 1.0) + 1.0;
    return a2 / (kPi * d * d);
  }
  TESSERA_HOST_DEVICE double smith_g1(double cos_v) const {
    const double a2 = alpha * alpha;
    const double c2 = cos_v * cos_v;
    return 2.0 * cos_v / (cos_v + std::sqrt(a2 + (1.0 - a2) * c2));
  }

  TESSERA_HOST_DEVICE Color eval(const Vec3& wo, const Vec3& wi) const {
    const double cos_o = glm::dot(n, wo), cos_i = glm::dot(n, wi);
    if (cos_i <= 0.0 || cos_o <= 0.0) return Color(0.0);
    Color f = albedo * kInvPi;
    if (p_spec > 0.0) {
      const Vec3 h = glm::normalize(wo + wi);
      const double cos_h = glm::dot(n, h), o_h = glm::dot(wo, h);
      const Color fresnel = f0 + (Color(1.0) - f0) * std::pow(1.0 - std::clamp(o_h, 0.0, 1.0), 5.0);
      f += fresnel * (ggx_d(cos_h) * smith_g1(cos_o) * smith_g1(cos_i) / (4.0 * cos_o * cos_i));
    }
    return f * cos_i;
  }

  TESSERA_HOST_DEVICE double pdf(const Vec3& wo, const Vec3& wi) const {
    const double cos_o = glm::dot(n, wo), cos_i = glm::dot(n, wi);
    if (cos_i <= 0.0 || cos_o <= 0.0) return 0.0;
    double p = (1.0 - p_spec) * cos_i * kInvPi;
    if (p_spec > 0.0) {
      const Vec3 h = glm::normalize(wo + wi);
      const double cos_h = glm::dot(n, h);
      p += p_spec * ggx_d(cos_h) * cos_h / (4.0 * glm::dot(wo, h));
    }
    return p;
  }

  /// Sample wi; returns false when the sample falls below the surface.
  TESSERA_HOST_DEVICE bool sample(const Vec3& wo, double u0, double u1, double u2, Vec3* wi) const {
    const Frame f(n);
    if (u0 < p_spec) {
      // GGX normal distribution sampling: D(h) cos(theta_h).
      const double a2 = alpha * alpha;
      const double cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
      const double cos_h = std::sqrt(std::fmax(0.0, cos2));
      const double sin_h = std::sqrt(std::fmax(0.0, 1.0 - cos2));
      const double phi = 2.0 * kPi * u2;
      const Vec3 h = f.to_world(Vec3(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h));
      *wi = 2.0 * glm::dot(wo, h) * h - wo;
    } else {
      *wi = f.to_world(cosine_hemisphere(u1, u2));
    }
    return glm::dot(n, *wi) > 0.0;
  }
};

}  // namespace tessera
