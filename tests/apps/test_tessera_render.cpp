// tessera-render end to end, on a small synthetic volume written by the test: outputs, -o,
// flag overrides, --stats, and one-line errors with exit status 1.
#include "../config/test_support.h"
#include "read_png.h"

#include <tessera/annotate.h>
#include <tessera/config/annotations.h>
#include <tessera/config/build_scene.h>
#include <tessera/cuda_render.h>
#include <tessera/image_io.h>
#include <tessera/tessera.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#ifndef TESSERA_RENDER_EXE
#error "TESSERA_RENDER_EXE must name the tessera-render executable"
#endif

using tessera::config::test::TempDir;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

struct Run {
  int status;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs tessera-render with `args` inside `dir`, capturing stdout and stderr.
Run run_cli(const TempDir& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.path().string() + "' && '" TESSERA_RENDER_EXE "' " + args + " > cli.out 2> cli.err";
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir.path() / "cli.out"), slurp(dir.path() / "cli.err")};
}

/// A 12^3 float32 Gaussian blob (values 300..400) and a scene with two renders.
void write_scene(const TempDir& dir) {
  const int n = 12;
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i - 5.5) / 3.0, y = (j - 5.5) / 3.0, z = (k - 5.5) / 3.0;
        v.push_back(static_cast<float>(300.0 + 100.0 * std::exp(-(x * x + y * y + z * z))));
      }
  std::ofstream(dir.file("blob.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("scene.yaml", R"(tessera:
  output_dir: results
volume:
  file: blob.raw
  dims: [12, 12, 12]
  dtype: float32
  spacing: [0.5, 0.5, 0.5]
renders:
  - name: front
    image: {width: 24, height: 16, spp: 2}
    camera:
      position: {orbit: {azimuth: 30, elevation: 20, distance: 3}}
    transfer_function:
      range: auto
      density_scale: 1.5
      opacity: [[0, 0], [1, 1]]
      diffuse: viridis
    lights:
      - {type: rect, position: {orbit: {azimuth: 0, elevation: 60, distance: 3}}, size: {relative: 0.5}, intensity: 5}
    background: {type: constant, color: [0.1, 0.1, 0.12]}
    integrator: {tile: 4}
  - name: side
    image: {width: 16, height: 16, spp: 1}
    camera: {position: [20, 2.75, 2.75]}
    transfer_function: {range: [300, 400], opacity: [[0, 0], [1, 1]]}
    output: {file: "{name}/img_{step:03d}", formats: [exr]}
)");
}

}  // namespace

TEST_CASE("tessera-render writes every render's outputs and statistics", "[cli]") {
  TempDir dir;
  write_scene(dir);
  const Run r = run_cli(dir, "scene.yaml --quiet --stats stats/run.json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.out.empty());
  CHECK(r.err.empty());
  CHECK(fs::exists(dir.path() / "results/front_000000.exr"));
  CHECK(fs::exists(dir.path() / "results/front_000000.png"));
  CHECK(fs::exists(dir.path() / "results/side/img_000.exr"));
  CHECK_FALSE(fs::exists(dir.path() / "results/side/img_000.png"));

  const tessera::Image img = tessera::read_exr(dir.file("results/front_000000.exr"));
  CHECK(img.width == 24);
  CHECK(img.height == 16);

  const std::string json = slurp(dir.path() / "stats/run.json");
  for (const char* key : {"wall_seconds", "samples", "samples_per_second", "density_lookups", "free_flight_lookups",
                          "transmittance_lookups", "real_collisions", "null_collisions", "nan_voxels_seen",
                          "discarded_samples", "tiles_total", "tiles_skipped", "threads", "lookups_per_real_collision",
                          "renders", "stalled_paths", "warnings"})
    CHECK_THAT(json, Contains(std::string("\"") + key + "\":"));
  // Totals: 24*16*2 + 16*16*1 samples
  CHECK_THAT(json, Contains("\"samples\": 1024,"));
  CHECK_THAT(json, Contains("\"name\": \"front\""));
  CHECK_THAT(json, Contains("\"name\": \"side\""));
}

TEST_CASE("tessera-render -o and flag overrides", "[cli]") {
  TempDir dir;
  write_scene(dir);

  // -o OUT without extension: OUT.exr and OUT.png per formats
  Run r = run_cli(dir, "scene.yaml --render front -o pics/one --spp 3 --width 20 --height 10");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Contains("front: 20x10, 3 spp"));
  CHECK(fs::exists(dir.path() / "pics/one.exr"));
  CHECK(fs::exists(dir.path() / "pics/one.png"));
  CHECK(tessera::read_exr(dir.file("pics/one.exr")).width == 20);

  // -o OUT.png: that format only; several renders get _NAME
  r = run_cli(dir, "scene.yaml -o two.png --quiet");
  REQUIRE(r.status == 0);
  CHECK(fs::exists(dir.path() / "two_front.png"));
  CHECK(fs::exists(dir.path() / "two_side.png"));
  CHECK_FALSE(fs::exists(dir.path() / "two_front.exr"));

  // Threads, tile size and scanline order do not change the image (bit-identical)
  REQUIRE(run_cli(dir, "scene.yaml --render front -o a.exr --threads 1 --tile 3 --quiet").status == 0);
  REQUIRE(run_cli(dir, "scene.yaml --render front -o b.exr --threads 2 --scanline --quiet").status == 0);
  REQUIRE(run_cli(dir, "scene.yaml --render front -o c.exr --seed 12345 --quiet").status == 0);
  const auto a = tessera::read_exr(dir.file("a.exr"));
  const auto b = tessera::read_exr(dir.file("b.exr"));
  const auto c = tessera::read_exr(dir.file("c.exr"));
  CHECK(a.rgba == b.rgba);
  CHECK(a.rgba != c.rgba);  // another seed, another noise
}

TEST_CASE("tessera-render errors are one line and exit status 1", "[cli]") {
  TempDir dir;
  write_scene(dir);
  const auto one_line_error = [](const Run& r) {
    CHECK(r.status == 1);
    CHECK_THAT(r.err, StartsWith("tessera-render: error: "));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  };

  Run r = run_cli(dir, "scene.yaml --render nope");
  one_line_error(r);
  CHECK_THAT(r.err, Contains("nope"));
  CHECK_THAT(r.err, Contains("front, side"));

  one_line_error(r = run_cli(dir, "scene.yaml --tile 4 --scanline"));
  one_line_error(r = run_cli(dir, "scene.yaml --spp zero"));
  CHECK_THAT(r.err, Contains("--spp"));
  one_line_error(r = run_cli(dir, "scene.yaml --frobnicate"));
  one_line_error(r = run_cli(dir, ""));
  one_line_error(r = run_cli(dir, "missing.yaml"));
  CHECK_THAT(r.err, Contains("missing.yaml"));

  // Config errors keep their file:line:col
  dir.write("bad.yaml", "renders:\n  - name: a\n    camera: {position: [0, 0, 5], fov: 270}\n");
  one_line_error(r = run_cli(dir, "bad.yaml"));
  CHECK_THAT(r.err, Contains("bad.yaml:3:35: renders[0].camera.fov: 270 is out of range (0, 180)"));

  // No volume block; a volume file of the wrong size
  dir.write("novol.yaml", "renders:\n  - name: a\n    camera: {position: [0, 0, 5]}\n"
                          "    transfer_function: {opacity: [[0, 1]]}\n");
  one_line_error(r = run_cli(dir, "novol.yaml"));
  CHECK_THAT(r.err, Contains("volume"));
  dir.write("short.raw", std::string(10, '\0'));
  dir.write("short.yaml", "volume: {file: short.raw, dims: [2, 2, 2], dtype: float32}\n"
                          "renders:\n  - name: a\n    camera: {position: [0, 0, 5]}\n"
                          "    transfer_function: {opacity: [[0, 1]]}\n");
  one_line_error(r = run_cli(dir, "short.yaml"));
  CHECK_THAT(r.err, Contains("expected 32"));

  // --help succeeds
  r = run_cli(dir, "--help");
  CHECK(r.status == 0);
  CHECK_THAT(r.out, Contains("usage: tessera-render SCENE.yaml"));
}

TEST_CASE("tessera-render --device: a bad word, the CPU, and the GPU or why not", "[cli][gpu]") {
  TempDir dir;
  write_scene(dir);
  Run r = run_cli(dir, "scene.yaml --device gpu");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Contains("--device: \"gpu\" is not a device (allowed: auto, cpu, cuda)"));
  r = run_cli(dir, "scene.yaml --render front --device cpu --quiet --stats cpu.json");
  CHECK(r.status == 0);
  CHECK_THAT(slurp(dir.path() / "cpu.json"), Contains("\"device\": \"cpu\""));
  // cuda: renders where a GPU is visible, else one line naming why (no CUDA build, no device)
  r = run_cli(dir, "scene.yaml --render front --device cuda --quiet --stats cuda.json");
  if (tessera::cuda_device_count() > 0) {
    CHECK(r.status == 0);
    CHECK_THAT(slurp(dir.path() / "cuda.json"), Contains("\"device\": \"cuda:0\""));
  } else {
    CHECK(r.status == 1);
    CHECK_THAT(r.err, StartsWith("tessera-render: error: tessera.device is cuda, but "));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

TEST_CASE("tessera-render --check validates the scene and the volume without rendering", "[cli]") {
  TempDir dir;
  write_scene(dir);
  const Run ok = run_cli(dir, "scene.yaml --check");
  INFO(ok.err);
  CHECK(ok.status == 0);
  CHECK(ok.out == "scene.yaml: ok (2 renders)\n");
  CHECK(ok.err.empty());
  CHECK_FALSE(fs::exists(dir.path() / "results"));  // nothing rendered or written
  CHECK(run_cli(dir, "scene.yaml --check --render side --quiet").out.empty());

  // A volume file of the wrong size fails as a render would, before any image
  std::ofstream(dir.file("blob.raw"), std::ios::binary | std::ios::app) << "x";
  const Run bad = run_cli(dir, "scene.yaml --check");
  CHECK(bad.status == 1);
  CHECK_THAT(bad.err, StartsWith("tessera-render: error: "));
  CHECK_THAT(bad.err, Contains("blob.raw"));
  CHECK_FALSE(fs::exists(dir.path() / "results"));

  CHECK_THAT(run_cli(dir, "--check=1 scene.yaml").err, Contains("--check takes no value"));
}

TEST_CASE("tessera-render warns, without failing, when the range misses the data", "[cli][warnings]") {
  TempDir dir;
  write_scene(dir);  // values in [300, 400]
  std::string yaml = slurp(dir.path() / "scene.yaml");
  const std::string side_range = "range: [300, 400]";
  REQUIRE(yaml.find(side_range) != std::string::npos);
  yaml.replace(yaml.find(side_range), side_range.size(), "range: [1000, 2000]");
  dir.write("scene.yaml", yaml);
  const Run r = run_cli(dir, "scene.yaml --render side --stats run.json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(fs::exists(dir.path() / "results/side/img_000.exr"));
  CHECK_THAT(r.err, Contains("tessera-render: warning: side: transfer_function.range [1000, 2000] misses the data's "
                             "values [300.004, 392.004]: nothing of the field is visible"));
  CHECK_THAT(r.err, Contains("nothing of the field is visible: 0 real collisions in 256 samples; likely cause: "
                             "transfer_function.range"));
  const std::string json = slurp(dir.path() / "run.json");
  CHECK_THAT(json, Contains("\"side: transfer_function.range [1000, 2000] misses the data's values [300"));
  CHECK_THAT(json, Contains("\"warnings\": [\"transfer_function.range [1000, 2000] misses"));
}

TEST_CASE("tessera-render warns when volume.dims look swapped and names the order that fits", "[cli][warnings]") {
  TempDir dir;
  // A smooth 24 x 12 x 6 field; the same bytes declared as [6, 12, 24] render as stripes
  std::vector<float> v;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 24; ++i) v.push_back(float(std::sin(0.25 * i) + std::cos(0.3 * j) + 0.2 * k));
  std::ofstream(dir.file("v.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  const auto scene = [](const char* dims) {
    return std::string("volume: {file: v.raw, dims: ") + dims + R"(, dtype: float32}
renders:
  - name: r
    image: {width: 8, height: 8, spp: 1}
    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}}
    transfer_function: {range: auto, opacity: [[0, 0], [1, 1]]}
)";
  };
  dir.write("right.yaml", scene("[24, 12, 6]"));
  dir.write("swapped.yaml", scene("[6, 12, 24]"));
  const Run right = run_cli(dir, "right.yaml --check");
  CHECK(right.status == 0);
  CHECK(right.err.empty());

  const Run check = run_cli(dir, "swapped.yaml --check");
  CHECK(check.status == 0);  // a warning never fails
  CHECK_THAT(check.err, Contains("tessera-render: warning: volume.dims [6, 12, 24] may be in the wrong order"));
  CHECK_THAT(check.err, Contains("dims [24, 12, 6] make the data smooth"));

  const Run render = run_cli(dir, "swapped.yaml --quiet --stats run.json");
  INFO(render.err);
  CHECK(render.status == 0);
  CHECK_THAT(render.err, Contains("tessera-render: warning: r: volume.dims [6, 12, 24] may be in the wrong order"));
  CHECK_THAT(slurp(dir.path() / "run.json"), Contains("volume.dims [6, 12, 24] may be in the wrong order"));
}

TEST_CASE("tessera-render --step N renders what the adapter renders at step N, bit for bit", "[cli][insitu]") {
  TempDir dir;
  const int n = 9;  // spacing 1/8: the same double in the YAML and the grid
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i - 4) / 2.0, y = (j - 4) / 2.0, z = (k - 4) / 2.0;
        v.push_back(static_cast<float>(std::exp(-(x * x + y * y + z * z))));
      }
  std::ofstream(dir.file("v.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  // One file for both: the adapter ignores `volume:`, the CLI reads it (same grid as below)
  dir.write("s.yaml", R"(tessera: {output_dir: out}
volume: {file: v.raw, dims: [9, 9, 9], dtype: float32, spacing: [0.125, 0.125, 0.125]}
renders:
  - name: r
    field: density
    trigger: {at: [7]}
    image: {width: 20, height: 14, spp: 3}
    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}}
    transfer_function: {range: auto, density_scale: 20, opacity: [[0, 0], [1, 1]]}
    lights: [{type: sphere, position: [2, 2, 2], radius: 0.3, intensity: 8}]
    integrator: {scattering: multiple}
    output: {file: "{name}_{step:04d}", formats: [exr]}
)");
  tessera_field f{};
  f.name = "density";
  f.data = v.data();
  f.dtype = TESSERA_FLOAT32;
  for (int a = 0; a < 3; ++a) f.dims[a] = n;
  f.byte_strides[0] = 4;
  f.byte_strides[1] = 4LL * n;
  f.byte_strides[2] = 4LL * n * n;
  tessera_grid g{};
  for (int a = 0; a < 3; ++a) {
    g.spacing[a] = 1.0 / (n - 1);
    g.global_dims[a] = n;
  }
  tessera_adapter* ad = nullptr;
  const std::string cfg = dir.file("s.yaml");
  REQUIRE(tessera_open_with_output_dir(cfg.c_str(), -1, dir.file("adapter").c_str(), &ad) == TESSERA_OK);
  REQUIRE(tessera_execute(ad, 7, 0.7, &g, &f, 1) == TESSERA_OK);
  REQUIRE(tessera_close(ad) == TESSERA_OK);

  const Run step7 = run_cli(dir, "s.yaml --step 7 --quiet");
  INFO(step7.err);
  REQUIRE(step7.status == 0);
  const tessera::Image from_adapter = tessera::read_exr(dir.file("adapter/r_0007.exr"));
  const tessera::Image from_cli = tessera::read_exr(dir.file("out/r_0007.exr"));  // {step} = 7 too
  CHECK(from_cli.rgba == from_adapter.rgba);

  REQUIRE(run_cli(dir, "s.yaml --quiet").status == 0);  // step 0: other random numbers
  CHECK(tessera::read_exr(dir.file("out/r_0000.exr")).rgba != from_adapter.rgba);
  CHECK_THAT(run_cli(dir, "s.yaml --step x").err, Contains("--step: \"x\" is not an integer"));
}

TEST_CASE("tessera-render --time T fills {time} in output names as the adapter's time argument does", "[cli]") {
  TempDir dir;
  std::vector<float> v(27, 0.5f);
  std::ofstream(dir.file("v.raw"), std::ios::binary)
      .write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
  dir.write("s.yaml", R"(tessera: {output_dir: out}
volume: {file: v.raw, dims: [3, 3, 3], dtype: float32}
renders:
  - name: r
    image: {width: 8, height: 6, spp: 1}
    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}}
    transfer_function: {range: [0, 1], opacity: [[0, 0], [1, 1]]}
    output: {file: "{name}_{step:03d}_{time:.2f}", formats: [exr]}
)");
  const Run r = run_cli(dir, "s.yaml --step 4 --time 1.25 --quiet");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(std::filesystem::exists(dir.file("out/r_004_1.25.exr")));
  REQUIRE(run_cli(dir, "s.yaml --quiet").status == 0);  // default time 0
  CHECK(std::filesystem::exists(dir.file("out/r_000_0.00.exr")));
  CHECK_THAT(run_cli(dir, "s.yaml --time nan").err, Contains("--time: \"nan\" is not a finite number"));
  CHECK_THAT(run_cli(dir, "s.yaml --time 1e999").err, Contains("is not a finite number"));
  CHECK(run_cli(dir, "s.yaml --time").status != 0);
}

TEST_CASE("tessera-render draws annotations into the PNG only, and refuses ones larger than the image",
          "[cli][annotate]") {
  TempDir dir;
  write_scene(dir);
  const std::string original = slurp(dir.path() / "scene.yaml");
  const auto with = [](std::string s, const std::string& from, const std::string& to) {
    const std::size_t p = s.find(from);
    REQUIRE(p != std::string::npos);
    return s.replace(p, from.size(), to);
  };
  const std::string notes = "    annotations: {colorbar: true, text: \"{name} step {step}\"}\n  - name: side";
  const std::string plain = with(original, "{width: 24, height: 16, spp: 2}", "{width: 128, height: 96, spp: 1}");
  dir.write("plain.yaml", plain);
  dir.write("noted.yaml", with(with(plain, "  - name: side", notes), "output_dir: results", "output_dir: noted"));
  Run r = run_cli(dir, "plain.yaml --render front --step 3 --quiet");
  INFO(r.err);
  REQUIRE(r.status == 0);
  r = run_cli(dir, "noted.yaml --render front --step 3 --quiet");
  REQUIRE(r.status == 0);
  CHECK(slurp(dir.path() / "results/front_000003.exr") == slurp(dir.path() / "noted/front_000003.exr"));
  int w = 0, h = 0;
  const auto a = tessera_test::read_png_rgba(dir.file("results/front_000003.png"), w, h);
  const auto b = tessera_test::read_png_rgba(dir.file("noted/front_000003.png"), w, h);
  CHECK(w == 128);
  CHECK(a != b);

  // The 24x16 image of the original scene has no room for them: a load-time error
  dir.write("tiny.yaml", with(original, "  - name: side", notes));
  r = run_cli(dir, "tiny.yaml --check");
  CHECK(r.status == 1);
  CHECK_THAT(r.err,
             Contains("tiny.yaml:") && Contains("renders[0].annotations") && Contains("more than the 24x16 image has"));
}

TEST_CASE("tessera-render writes distinct colour-bar labels for a narrow range far from zero", "[cli][annotate]") {
  // A pressure of 101325 +- 0.05 with ten ticks: each label must differ from its neighbours in
  // the picture itself (on a black background with nothing rendered, equal texts give equal
  // pixels)
  TempDir dir;
  write_scene(dir);
  const std::string yaml = R"(volume: {file: blob.raw, dims: [12, 12, 12], dtype: float32}
renders:
  - name: p
    image: {width: 160, height: 256, spp: 1}
    camera: {position: [20, 2.75, 2.75]}
    transfer_function: {range: [101324.95, 101325.05], opacity: [[0, 0], [1, 0]]}
    background: {type: constant, color: [0, 0, 0]}
    output: {formats: [png]}
    annotations: {colorbar: {ticks: 10, length: 0.9}}
)";
  dir.write("p.yaml", yaml);
  const Run r = run_cli(dir, "p.yaml --quiet -o p");
  INFO(r.err);
  REQUIRE(r.status == 0);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> px = tessera_test::read_png_rgba(dir.file("p.png"), w, h);
  REQUIRE(w == 160);

  // Where the labels are: the layout of the same description
  const tessera::config::Config c = tessera::config::parse_config(yaml, dir.file("p.yaml"), dir.path().string());
  const tessera::config::RenderSpec& spec = c.renders[0];
  const tessera::TransferFunction tf = tessera::config::build_transfer_function(spec.transfer_function, {0.0, 1.0});
  const tessera::AnnotationDesc d =
      tessera::config::build_annotations(*spec.annotations, spec.name, spec.field, tf, 0, 0.0);
  const tessera::AnnotationLayout l = tessera::layout_annotations(w, h, d);
  REQUIRE(l.tick_labels.size() >= 5u);
  const auto crop = [&](const tessera::PixelBox& b) {  // inner rows: free of a neighbour's outline
    std::vector<std::uint8_t> out;
    for (int y = b.y0 + 2; y < b.y1 - 2; ++y)
      for (int x = b.x0; x < b.x1; ++x)
        for (int k = 0; k < 4; ++k) out.push_back(px[(static_cast<std::size_t>(y) * w + x) * 4 + k]);
    return out;
  };
  for (std::size_t i = 1; i < l.tick_labels.size(); ++i) {
    INFO("labels " << i - 1 << " and " << i);
    CHECK(crop(l.tick_labels[i - 1]) != crop(l.tick_labels[i]));
  }
}
