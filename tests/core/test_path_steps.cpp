// PathSteps (kernel/path_steps.h), the step-level loop's path: run one call at a time it must
// be PathTracer::li exactly (the same sample, counters and random numbers drawn), and each
// call must take at most one tracking step (one free-flight or transmittance lookup; the
// fixed-step march, which is not resumable, runs whole in one call).
#include <tessera/render.h>

#include <catch2/catch.hpp>

#include "kernel/kernel_dispatch.h"
#include "kernel/path_steps.h"
#include "kernel/path_tracer.h"
#include "same_paths.h"
#include "scene/prepared_scene_impl.h"
#include "test_support.h"

#include <cstring>
#include <vector>

using tessera::Color;
using tessera::Vec3;

namespace {

/// A blobby field with what every phase meets: lights of both kinds (one inside the volume)
/// and an emitting background, emission, hybrid shading with a specular lobe.
tessera::SceneDesc steps_scene(int n) {
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.density_scale = 14.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.2, 1.0}, {0.0, 0.5, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.5, 0.2), Color(0.3, 0.6, 0.9)});
  s.tf.specular = tessera::ColorTF::constant(Color(0.2));
  s.tf.emission = tessera::ColorTF({0.6, 1.0}, {Color(0.0), Color(0.5)});
  s.camera.position = Vec3(0.5, 0.6, -1.2);
  s.camera.look_at = Vec3(0.5);
  s.camera.fov_deg = 55.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.8, 0.5), Vec3(0.5, 0.0, 0.5), 1.0, 1.0, Color(3.0)});
  s.lights.push_back(tessera::RectLightDesc{Vec3(-1.0, 0.5, 0.5), Vec3(0.5), 0.8, 0.8, Color(2.0)});
  s.lights.push_back(tessera::SphereLightDesc{Vec3(0.5, 0.45, 0.5), 0.1, Color(4.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 4;
  s.integrator.rr_depth = 2;
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.macrocell = 4;
  s.image = {12, 12, 6, 0.0};
  s.options.seed = 5;
  return s;
}

bool same_bits(const tessera::SampleResult& a, const tessera::SampleResult& b) {
  return std::memcmp(&a.L, &b.L, sizeof a.L) == 0 && std::memcmp(&a.alpha, &b.alpha, sizeof a.alpha) == 0 &&
         std::memcmp(&a.albedo, &b.albedo, sizeof a.albedo) == 0 &&
         std::memcmp(&a.normal, &b.normal, sizeof a.normal) == 0;
}

}  // namespace

TEST_CASE("PathSteps is PathTracer::li one tracking step at a time", "[path_tracer]") {
  constexpr int n = 16;
  const std::vector<float> field = tessera_test::blobby_field(n, n, n);
  for (const auto shadow : {tessera::ShadowMode::Ratio, tessera::ShadowMode::Delta})
    for (const auto path : {tessera::FreePath::Delta, tessera::FreePath::Raymarch}) {
      tessera::SceneDesc s = steps_scene(n);
      s.integrator.shadow = shadow;
      s.integrator.free_path = path;
      const tessera::PreparedScene ps =
          tessera::prepare(tessera::FieldView::contiguous(field.data(), tessera::DType::Float32, n, n, n), s);
      const tessera::KernelScene& ks = tessera::prepared_scene_impl(ps).kernel;
      const tessera::GridMedium<float> m = tessera::make_medium<float>(ks);
      const tessera::PathTracer<float> tracer(ks, m);
      using Steps = tessera::PathSteps<float>;
      tessera::RenderStats k_li, k_steps;
      std::uint64_t calls = 0, collisions = 0, last_bounces = 0;
      bool one_step = true, same = true;
      for (int y = 0; y < ks.height; ++y)
        for (int x = 0; x < ks.width; ++x)
          for (std::uint64_t i = 0; i < 6; ++i) {
            const std::uint64_t pixel = static_cast<std::uint64_t>(y) * ks.width + x;
            const tessera::Ray ray = ks.camera.generate(x + 0.25 + 0.1 * i, y + 0.5, 0.5, 0.5);
            const tessera::SobolSampler ld(5, 0, pixel, i);
            const tessera::SobolSampler* lp = i % 2 ? &ld : nullptr;  // both samplers
            tessera::Rng a(5, 0, pixel, i), b(5, 0, pixel, i);
            const tessera::SampleResult r = tracer.li(ray, a, k_li, lp);
            Steps::State st = Steps::begin(ray);
            for (;;) {
              const std::uint64_t f0 = k_steps.free_flight_lookups, t0 = k_steps.transmittance_lookups;
              const bool live = Steps::advance(tracer, st, b, k_steps, lp);
              ++calls;
              // (the biased fixed-step march is not resumable: it runs whole in one call)
              const std::uint64_t f = path == tessera::FreePath::Delta ? k_steps.free_flight_lookups - f0 : 0;
              one_step = one_step && f + (k_steps.transmittance_lookups - t0) <= 1;
              if (!live) break;
            }
            last_bounces += st.path.depth >= ks.max_depth;
            same = same && same_bits(r, st.path.out) && a.next_u64() == b.next_u64();
          }
      INFO("shadow " << static_cast<int>(shadow) << ", free path " << static_cast<int>(path));
      CHECK(same);
      CHECK(one_step);
      tessera_test::check_same_paths(k_li, k_steps);
      CHECK(k_steps.stalled_paths == k_li.stalled_paths);
      collisions = k_li.real_collisions;
      CHECK(collisions > 100);    // the paths scatter
      CHECK(last_bounces > 10);   // and some reach the depth limit (the last bounce's emitters)
      CHECK(calls > collisions);  // more than one call a bounce: the walks are split
    }
}
