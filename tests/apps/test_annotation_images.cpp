// The annotations picture of docs/config.md is what its documented commands make: the
// tessera-synth and tessera-render lines of scripts/make_doc_images.sh, rerun here on a copy of
// docs/images/annotations.yaml (only the volume's path changed), give the committed PNG's
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
using tessera_test::run_command;

TEST_CASE("the annotations picture of docs/config.md is made by its documented commands", "[cli][docs][annotate]") {
  const std::string repo = std::string(TESSERA_TEST_DATA_DIR) + "/../..";
  TempDir dir;
  REQUIRE(run_command("'" TESSERA_SYNTH_EXE "' '" + dir.file("blobs.raw") +
                      "' --dims 64 64 64 --kind blobs > /dev/null") == 0);
  const std::string yaml = tessera_test::doc_yaml_with_volume(repo + "/docs/images/annotations.yaml", "/tmp/blobs.raw",
                                                              dir.file("blobs.raw"));
  REQUIRE(!yaml.empty());
  dir.write("annotations.yaml", yaml);
  REQUIRE(run_command("'" TESSERA_RENDER_EXE "' '" + dir.file("annotations.yaml") + "' --step 120 -o '" +
                      dir.file("annotations.png") + "' --quiet") == 0);
  int w = 0, h = 0, cw = 0, ch = 0;
  const std::vector<std::uint8_t> made = tessera_test::read_png_rgba(dir.file("annotations.png"), w, h);
  const std::vector<std::uint8_t> committed =
      tessera_test::read_png_rgba(repo + "/docs/images/annotations.png", cw, ch);
  CHECK(w == 480);
  CHECK(h == 320);
  CHECK(made == committed);
}
