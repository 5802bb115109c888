#pragma once
/// Shared by test_loops.cpp and test_scene_checks.cpp: a small lit cloud (core scene and the
/// same as a tessera-render config), a timed render and a timed CLI run. Test code only.
#include <tessera/film.h>
#include <tessera/image.h>
#include <tessera/render.h>
#include <tessera/scene.h>

#include "cli_run.h"
#include "temp_dir.h"

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace tessera_test {

/// A 16^3 float32 ball: 1 at the centre falling to 0 at radius 8 voxels.
inline std::vector<float> ball_field(int n = 16) {
  std::vector<float> v;
  v.reserve(static_cast<std::size_t>(n) * n * n);
  const double c = 0.5 * (n - 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double r = std::sqrt((i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c)) / (0.5 * n);
        v.push_back(static_cast<float>(std::max(0.0, 1.0 - r)));
      }
  return v;
}

inline tessera::FieldView ball_view(const std::vector<float>& v, int n = 16) {
  return tessera::FieldView::contiguous(v.data(), tessera::DType::Float32, n, n, n);
}

/// The ball at spacing 0.1 (box [0, 1.5]^3), a sharp opacity ramp, a sphere light,
/// multiple scattering, 16x16 at 4 spp.
inline tessera::SceneDesc ball_scene() {
  using tessera::Vec3;
  tessera::SceneDesc s;
  s.geometry.spacing = Vec3(0.1);
  s.tf.lo = 0.0;
  s.tf.hi = 1.0;
  s.tf.density_scale = 20.0;
  s.tf.opacity = tessera::ScalarTF({0.0, 0.5, 0.7, 1.0}, {0.0, 0.0, 0.5, 1.0});
  s.tf.diffuse = tessera::ColorTF::constant(tessera::Color(0.8));
  s.camera.position = Vec3(3.5, -2.5, 2.9);
  s.camera.look_at = Vec3(0.75);
  s.camera.up = Vec3(0.0, 0.0, 1.0);
  s.camera.fov_deg = 35.0;
  s.lights.push_back(tessera::SphereLightDesc{Vec3(0.2, 2.5, 3.0), 0.3, tessera::Color(12.0)});
  s.background.color = tessera::Color(0.15);
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.integrator.max_bounces = 16;
  s.image = {16, 16, 4, 0.0};
  s.options.seed = 7;
  s.options.threads = 2;
  return s;
}

struct TimedRender {
  tessera::Film film;
  tessera::RenderStats stats;
  double seconds = 0.0;
};

inline TimedRender timed_render(const tessera::FieldView& view, const tessera::SceneDesc& s) {
  TimedRender r;
  const auto t0 = std::chrono::steady_clock::now();
  const tessera::PreparedScene p = tessera::prepare(view, s);
  r.film = tessera::Film(s.image.width, s.image.height);
  tessera::render(p, r.film, r.stats);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

inline bool film_finite(const tessera::Film& f) {
  for (const tessera::PixelSums& p : f.pixels())
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b) || !std::isfinite(p.a)) return false;
  return true;
}

/// The ball as a raw file plus a tessera-render config; `subst` replaces the placeholders
/// SPACING, ORIGIN, CAMPOS, FOV, APERTURE, DENS, OPAC, LIGHT, FREEPATH, STEP, BOUNCES.
inline void write_ball_config(const TempDir& dir, std::map<std::string, std::string> subst) {
  const std::vector<float> v = ball_field();
  std::ofstream(dir.file("ball.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  const std::map<std::string, std::string> defaults = {
      {"SPACING", "[0.1, 0.1, 0.1]"},
      {"ORIGIN", "[0, 0, 0]"},
      {"CAMPOS", "{orbit: {azimuth: 35, elevation: 25, distance: 2.6}}"},
      {"FOV", "35"},
      {"APERTURE", "0"},
      {"DENS", "20"},
      {"OPAC", "0.5"},
      {"LIGHT", "{type: sphere, position: {orbit: {azimuth: -40, elevation: 50, distance: 2.2}}, "
                "radius: {relative: 0.25}, color: [1, 1, 1], intensity: 12}"},
      {"FREEPATH", "delta"},
      {"STEP", "0.5"},
      {"BOUNCES", "16"}};
  for (const auto& [k, v2] : defaults) subst.emplace(k, v2);
  std::string text = R"(tessera:
  output_dir: out
  threads: 2
volume:
  file: ball.raw
  dims: [16, 16, 16]
  dtype: float32
  spacing: SPACING
  origin: ORIGIN
renders:
  - name: r
    image: {width: 16, height: 16, spp: 4}
    camera:
      position: CAMPOS
      look_at: center
      up: [0, 0, 1]
      fov: FOV
      aperture: APERTURE
    transfer_function:
      range: [0.0, 1.0]
      density_scale: DENS
      opacity: [[0.0, 0.0], [0.5, 0.0], [0.7, OPAC], [1.0, 1.0]]
      diffuse: [[0.0, [0.8, 0.8, 0.8]], [1.0, [0.8, 0.8, 0.8]]]
    lights:
      - LIGHT
    background: {type: constant, color: [0.15, 0.17, 0.22], intensity: 1.0}
    integrator:
      scattering: multiple
      max_bounces: BOUNCES
      free_path: FREEPATH
      step: STEP
    output:
      file: "{name}"
      formats: [exr]
)";
  for (const auto& [k, v2] : subst)
    for (std::size_t p; (p = text.find(k)) != std::string::npos;) text.replace(p, k.size(), v2);
  dir.write("scene.yaml", text);
}

/// tessera-render under `timeout 60` inside `dir` (cli_run.h).
inline CliRun run_render_cli(const TempDir& dir, const std::string& args) { return run_cli(dir, args); }

inline bool image_finite(const tessera::Image& im) {
  for (const float v : im.rgba)
    if (!std::isfinite(v)) return false;
  return !im.rgba.empty();
}

}  // namespace tessera_test
