#pragma once
/// Scenes of the accuracy suite that the accuracy benchmark (bench/accuracy) runs again with
/// more samples, written once so that the benchmark's figures are those of the tested scenes.
/// Each builder leaves `image` and `options.seed` to the caller (they differ between the test
/// and the benchmark). Header-only; no test framework.
#include "accuracy_support.h"

namespace tessera_acc {

/// White furnace (test_furnace_reference.cpp): the unit box sampled by 5^3 vertices (render
/// it with constant_field(5, 5, 5, 1.0f)), optical thickness tau, albedo 1, Henyey-Greenstein
/// g, multiple scattering with no practical bounce limit, inside a constant background of
/// radiance L: every pixel's expected value is L.
inline tessera::SceneDesc furnace_scene(double tau, double g, double L) {
  tessera::SceneDesc s = unit_box_scene(tau, 1.0);
  s.geometry.spacing = Vec3(0.25);  // 5^3 vertices, macrocells of 2 voxels
  s.integrator.macrocell = 2;
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 1 << 30;
  s.integrator.phase_g = g;
  s.background.color = Color(L);
  s.camera.position = Vec3(1.9, 1.4, -1.5);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 28.0;
  return s;
}

/// Convergence (test_convergence.cpp): a heterogeneous cloud of n^3 vertices in the unit box
/// (render it with cloud_field(n, n, n)), hybrid shading with a specular lobe, a rect light and
/// a gradient background, single scattering.
inline tessera::SceneDesc convergence_scene(int n) {
  tessera::SceneDesc s = unit_box_scene(20.0, 0.8);
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 0.6, 1.0}, {0.0, 0.2, 1.0, 1.0});
  s.tf.specular = tessera::ColorTF::constant(Color(0.04));
  s.integrator.shading = tessera::Shading::Hybrid;
  s.integrator.gradient_factor = 2.0;
  s.camera.position = Vec3(1.5, 1.2, -1.6);
  s.camera.look_at = Vec3(0.5, 0.5, 0.5);
  s.camera.fov_deg = 36.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 1.9, 0.3), Vec3(0.5, 0.0, 0.5), 0.8, 0.8, Color(5.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.up = Vec3(0.0, 1.0, 0.0);
  return s;
}

/// Ray-march bias (test_raymarch_bias.cpp): an absorbing box of n^3 vertices (render it with
/// raymarch_field(n, scale) of raymarch_model.h), extinction = scale * value, in front of a
/// constant background of radiance 1.
inline tessera::SceneDesc raymarch_scene(int n, double scale) {
  tessera::SceneDesc s = unit_box_scene(scale, 0.0);
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.opacity = tessera::ScalarTF({0.0, 1.0}, {0.0, 1.0});
  s.background.color = Color(1.0);
  s.integrator.macrocell = 4;
  // Every ray enters through the face z = 0: no silhouette, smooth pixel integrands.
  s.camera.position = Vec3(0.5, 0.5, -1.5);
  s.camera.look_at = Vec3(0.5, 0.52, 0.5);
  s.camera.fov_deg = 24.0;
  return s;
}

}  // namespace tessera_acc
