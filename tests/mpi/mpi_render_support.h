#pragma once
/// Helpers for the MPI render tests: the shared test scene and bit-for-bit comparisons of
/// films and counters.
#include <tessera/render.h>

#include <cstring>

namespace tessera_mpi_test {

/// The MPI tests' scene over a field with spacing 0.05 and values in [0, 250]: hybrid
/// shading, emission, a rect light above the volume, a gradient background. The caller adds
/// its sphere light and sets where the camera looks, the image, seed and frame.
inline tessera::SceneDesc base_scene(tessera::Scattering scattering, int threads) {
  using tessera::Color;
  using tessera::Vec3;
  tessera::SceneDesc s;
  s.geometry.origin = Vec3(0.0);
  s.geometry.spacing = Vec3(0.05);
  s.tf.lo = 0.0;
  s.tf.hi = 250.0;
  s.tf.density_scale = 20.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.15, 0.5, 1.0}, {0.0, 0.3, 0.8, 1.0});
  s.tf.diffuse = tessera::ColorTF({0.0, 1.0}, {Color(0.9, 0.6, 0.3), Color(0.3, 0.7, 0.95)});
  s.tf.specular = tessera::ColorTF::constant(Color(0.04));
  s.tf.emission = tessera::ColorTF({0.0, 0.6, 1.0}, {Color(0.0), Color(0.0), Color(2.0, 0.5, 0.1)});
  s.camera.position = Vec3(2.8, -1.6, 1.4);
  s.camera.up = Vec3(0.0, 0.0, 1.0);
  s.camera.fov_deg = 45.0;
  s.lights.push_back(tessera::RectLightDesc{Vec3(0.5, 0.5, 2.5), Vec3(0.5, 0.5, 0.4), 1.0, 1.0, Color(5.0, 4.0, 3.0)});
  s.background.type = tessera::BackgroundType::Gradient;
  s.background.top = Color(0.4, 0.5, 0.8);
  s.background.middle = Color(0.3);
  s.background.bottom = Color(0.05);
  s.integrator.scattering = scattering;
  s.integrator.max_bounces = 8;
  s.integrator.macrocell = 4;
  s.options.tile = 8;
  s.options.threads = threads;
  return s;
}

/// Pixels, and the denoiser's auxiliary sums when the films have them, bit for bit.
inline bool same_pixels(const tessera::Film& a, const tessera::Film& b) {
  return a.width() == b.width() && a.height() == b.height() && a.has_aux() == b.has_aux() &&
         std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(tessera::PixelSums)) == 0 &&
         (a.aux().empty() ||  // no auxiliary sums: data() may be null, which memcmp must not get
          std::memcmp(a.aux().data(), b.aux().data(), a.aux().size() * sizeof(tessera::AuxSums)) == 0);
}

/// Every counter of kRenderCounters (summed over ranks, or the field's NaN count) equal.
inline bool same_counters(const tessera::RenderStats& a, const tessera::RenderStats& b) {
  for (const tessera::RenderCounter& c : tessera::kRenderCounters)
    if (a.*c.field != b.*c.field) return false;
  return true;
}

}  // namespace tessera_mpi_test
