// tessera-render with a keyframed camera: --step picks the step, the keyframe's own step renders
// its static camera bit for bit, and a step whose pose makes no camera is a one-line error.
#include "../config/test_support.h"

#include <tessera/image_io.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef TESSERA_RENDER_EXE
#error "TESSERA_RENDER_EXE must name the tessera-render executable"
#endif

using tessera::config::test::TempDir;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

struct Run {
  int status;
  std::string err;
};

/// Runs tessera-render with `args` inside `dir`, capturing stderr.
Run run_cli(const TempDir& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir.path().string() + "' && '" TESSERA_RENDER_EXE "' " + args + " 2> cli.err";
  const int raw = std::system(cmd.c_str());
  std::ifstream in(dir.path() / "cli.err");
  std::ostringstream s;
  s << in.rdbuf();
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, s.str()};
}

/// A config over a 9^3 Gaussian blob (v.raw, written once) whose camera is `camera`.
std::string scene(const std::string& camera) {
  return "tessera: {output_dir: out}\n"
         "volume: {file: v.raw, dims: [9, 9, 9], dtype: float32}\n"
         "renders:\n  - name: r\n    image: {width: 20, height: 14, spp: 3}\n    camera: {" +
         camera +
         "}\n    transfer_function: {range: auto, density_scale: 20, opacity: [[0, 0], [1, 1]]}\n"
         "    lights: [{type: sphere, position: [12, 12, 12], radius: 2, intensity: 8}]\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

}  // namespace

TEST_CASE("tessera-render --step with a keyframed camera", "[cli][keyframes]") {
  TempDir dir;
  std::vector<float> v;
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i)
        v.push_back(static_cast<float>(std::exp(-0.2 * ((i - 4) * (i - 4) + (j - 4) * (j - 4) + (k - 4) * (k - 4)))));
  std::ofstream(dir.file("v.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("keyed.yaml", scene("keyframes: [{step: 0, position: {orbit: {azimuth: 0, elevation: 10, distance: fit}}}, "
                                "{step: 10, position: [20, 14, 9], look_at: [4, 4, 3], fov: 45}]"));
  dir.write("last.yaml", scene("position: [20, 14, 9], look_at: [4, 4, 3], fov: 45"));
  const auto image = [&](const std::string& config, int step) {
    const Run r = run_cli(dir, config + " --step " + std::to_string(step) + " --quiet -o img");
    INFO(r.err);
    REQUIRE(r.status == 0);
    return tessera::read_exr(dir.file("img.exr")).rgba;
  };
  // At the keyframe's step and after it (held): the static camera of that keyframe
  CHECK(image("keyed.yaml", 10) == image("last.yaml", 10));
  CHECK(image("keyed.yaml", 25) == image("last.yaml", 25));
  // Between the keyframes the camera is elsewhere
  CHECK(image("keyed.yaml", 5) != image("last.yaml", 5));

  // The camera passes through what it looks at, at step 5: that step fails, naming it
  dir.write("through.yaml", scene("keyframes: [{step: 0, position: [-4, 4, 4], look_at: [4, 4, 4]}, "
                                  "{step: 10, position: [12, 4, 4], look_at: [4, 4, 4]}]"));
  const Run bad = run_cli(dir, "through.yaml --step 5 --quiet");
  CHECK(bad.status == 1);
  CHECK_THAT(bad.err, Contains("camera.keyframes at step 5 (between keyframes 0 and 1, steps 0 and 10): position "
                               "[4, 4, 4] equals look_at"));
  CHECK(run_cli(dir, "through.yaml --step 4 --quiet").status == 0);
}
