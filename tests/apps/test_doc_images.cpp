// The pictures of docs/config.md "Moving cameras" are what their documented commands make:
// scripts/make_doc_images.sh's tessera-synth and tessera-render lines, rerun here on a copy of
// docs/images/moving_cameras.yaml (only the volume's path changed), give the committed PNGs'
// pixels exactly (decoded, so that a different zlib does not matter).
#include "../config/test_support.h"
#include "doc_yaml.h"

#include <png.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#if !defined(TESSERA_RENDER_EXE) || !defined(TESSERA_SYNTH_EXE) || !defined(TESSERA_TEST_DATA_DIR)
#error "needs TESSERA_RENDER_EXE, TESSERA_SYNTH_EXE and TESSERA_TEST_DATA_DIR"
#endif

using tessera::config::test::TempDir;

namespace {

const std::string kRepo = std::string(TESSERA_TEST_DATA_DIR) + "/../..";

/// RGBA bytes of a PNG, or empty when it cannot be read.
std::vector<std::uint8_t> pixels(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&img, path.c_str()) == 0) return {};
  img.format = PNG_FORMAT_RGBA;
  std::vector<std::uint8_t> px(PNG_IMAGE_SIZE(img));
  if (png_image_finish_read(&img, nullptr, px.data(), 0, nullptr) == 0) return {};
  return px;
}

int run(const std::string& cmd) {
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

}  // namespace

TEST_CASE("the moving-camera pictures of docs/config.md are made by their documented commands", "[cli][docs]") {
  TempDir dir;
  REQUIRE(run("'" TESSERA_SYNTH_EXE "' '" + dir.file("ramp.raw") + "' --dims 32 32 32 --kind linear > /dev/null") == 0);
  const std::string yaml = tessera_test::doc_yaml_with_volume(kRepo + "/docs/images/moving_cameras.yaml",
                                                              "/tmp/ramp.raw", dir.file("ramp.raw"));
  REQUIRE(!yaml.empty());
  dir.write("moving_cameras.yaml", yaml);
  // A turning orbit's frame and a keyframed camera between keyframes (smooth) and at one
  const struct {
    const char* render;
    int step;
    const char* picture;
  } cases[] = {{"turn", 30, "moving_turn_0030"}, {"fly", 15, "moving_fly_0015"}, {"fly", 60, "moving_fly_0060"}};
  for (const auto& c : cases) {
    INFO(c.picture);
    REQUIRE(run("'" TESSERA_RENDER_EXE "' '" + dir.file("moving_cameras.yaml") + "' --render " + c.render + " --step " +
                std::to_string(c.step) + " -o '" + dir.file(c.picture) + "' --quiet") == 0);
    const std::vector<std::uint8_t> made = pixels(dir.file(std::string(c.picture) + ".png"));
    const std::vector<std::uint8_t> committed = pixels(kRepo + "/docs/images/" + c.picture + ".png");
    REQUIRE(made.size() == 160u * 160u * 4u);
    CHECK(made == committed);
  }
}
