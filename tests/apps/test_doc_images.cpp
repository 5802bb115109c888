// The pictures of docs/config.md "Moving cameras" are what their documented commands make:
// scripts/make_doc_images.sh's tessera-synth and tessera-render lines, rerun here on a copy of
// docs/images/moving_cameras.yaml (only the volume's path changed), give the committed PNGs'
// pixels exactly (decoded, so that a different zlib does not matter).
#include "../config/test_support.h"
#include "doc_pictures.h"
#include "read_png.h"

#include <cstdint>
#include <string>
#include <vector>

#if !defined(TESSERA_RENDER_EXE) || !defined(TESSERA_SYNTH_EXE) || !defined(TESSERA_TEST_DATA_DIR)
#error "needs TESSERA_RENDER_EXE, TESSERA_SYNTH_EXE and TESSERA_TEST_DATA_DIR"
#endif

using tessera::config::test::TempDir;

using tessera_test::read_png_rgba;
using tessera_test::run_command;

namespace {

const std::string kRepo = std::string(TESSERA_TEST_DATA_DIR) + "/../..";

}  // namespace

TEST_CASE("the moving-camera pictures of docs/config.md are made by their documented commands", "[cli][docs]") {
  TempDir dir;
  REQUIRE(run_command("'" TESSERA_SYNTH_EXE "' '" + dir.file("ramp.raw") +
                      "' --dims 32 32 32 --kind linear > /dev/null") == 0);
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
    REQUIRE(run_command("'" TESSERA_RENDER_EXE "' '" + dir.file("moving_cameras.yaml") + "' --render " + c.render +
                        " --step " + std::to_string(c.step) + " -o '" + dir.file(c.picture) + "' --quiet") == 0);
    int w = 0, h = 0, cw = 0, ch = 0;
    const std::vector<std::uint8_t> made = read_png_rgba(dir.file(std::string(c.picture) + ".png"), w, h);
    const std::vector<std::uint8_t> committed = read_png_rgba(kRepo + "/docs/images/" + c.picture + ".png", cw, ch);
    REQUIRE(made.size() == 160u * 160u * 4u);
    CHECK(made == committed);
  }
}
