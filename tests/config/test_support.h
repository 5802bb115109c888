#pragma once
// Shared by the config tests: a scratch directory (TempDir, from tests/common) and a complete
// sample config.
#include <tessera/config/config.h>

#include <catch2/catch.hpp>

#include "temp_dir.h"

#include <string>

namespace tessera::config::test {

using tessera_test::TempDir;

/// The message of the ConfigError that parsing `yaml` throws, or "" if it parses.
inline std::string config_error(const std::string& yaml, const std::string& base_dir = "") {
  try {
    parse_config(yaml, "scene.yaml", base_dir);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// Every key of the schema, non-default values where possible. Needs `head.raw` next to it.
inline const char* full_config_yaml() {
  return R"(tessera:
  output_dir: images
  on_error: disable
  threads: 4
  render_final_step: true
  max_failures: 5
volume:
  file: head.raw
  dims: [4, 3, 2]
  dtype: uint16
  spacing: [0.5, 0.25, 2]
  origin: [1, 2, 3]
  byte_order: big
  header_bytes: 16
renders:
  - name: close
    field: temperature
    trigger: {every: 10}
    image: {width: 320, height: 200, spp: 8, target_error: 0.01, denoise: true}
    camera:
      position: [2.0, 1.5, 2.5]
      look_at: [0.5, 0.5, 0.5]
      up: [0, 1, 0]
      fov: 45
      aperture: 0.1
      focus_distance: 3
    transfer_function:
      range: [280, 400]
      density_scale: 20.0
      opacity:   [[0.0, 0.0], [0.4, 0.0], [1.0, 1.0]]
      diffuse:   [[0.0, [0.1, 0.2, 0.9]], [1.0, [0.9, 0.2, 0.1]]]
      specular:  [[0.0, [0.04, 0.04, 0.04]]]
      roughness: [[0.0, 0.5], [1.0, 0.25]]
      emission:  [[0.0, [0.0, 0.0, 0.0]], [1.0, [2.0, 1.0, 0.5]]]
    lights:
      - {type: rect, position: [0, 0, 3], target: [0.5, 0.5, 0.5], size: [1, 2], color: [1, 1, 1], intensity: 10}
      - {type: sphere, position: [3, 0, 0], radius: 0.2, color: [1, 0.9, 0.8], intensity: 50}
      - {type: rect, position: {orbit: {azimuth: 90, elevation: 45, distance: 3}}, size: {relative: 0.5}}
      - {type: sphere, position: center, radius: {relative: 0.1}}
    background: {type: gradient, top: [0.9, 0.9, 1], middle: [0.5, 0.5, 0.5], bottom: [0.1, 0.1, 0.1], up: [0, 1, 0], intensity: 2, visible: false}
    integrator:
      scattering: multiple
      max_bounces: 32
      rr_depth: 5
      shading: brdf
      gradient_factor: 2.5
      phase_g: -0.3
      free_path: raymarch
      majorant: global
      macrocell: 8
      step: 0.25
      shadow: delta
      shadow_roulette: false
      sampler: independent
      seed: 18446744073709551615
      tile: 0
      tile_order: morton
    output:
      file: "{name}/frame_{step:04d}_r{rank}"
      formats: [png]
      exposure: 1.5
      tonemap: reinhard
      variance: true
      samples: true
      cinema: {azimuth: [0, 90], elevation: [-30, 30]}
    annotations:
      colorbar: {corner: top-right, orientation: horizontal, length: 0.5, thickness: 0.05, ticks: 4, label: "T [K]"}
      text: "{name}  step {step:05d}  t = {time:.3g}"
      text_corner: bottom-left
      title: "Close view"
      title_corner: top-left
      font: /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
      font_size: 0.04
  - name: wide-2
    trigger: {at: [0, 5, 100]}
    camera:
      position: {orbit: {azimuth: 30, elevation: 20, distance: 2.5}}
      look_at: center
    transfer_function:
      range: auto
      opacity: [[0, 0], [1, 1]]
      diffuse: viridis
  - name: hot_spot
    trigger: {when: {above: 350}}
    camera: {position: [0, 0, 10]}
    transfer_function: {opacity: [[0, 1]], diffuse: magma_r}
    background: {type: constant, color: [0.2, 0.2, 0.25]}
)";
}

}  // namespace tessera::config::test
