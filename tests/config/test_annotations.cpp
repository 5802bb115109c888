// `annotations:`: keys, defaults, the write-back, the text patterns, and every bad value as a
// load-time error with file:line:col (unknown placeholders, runaway text, fractions out of
// range, unknown corners, a colour bar larger than the image, missing or unreadable fonts).
#include <tessera/config/annotations.h>
#include <tessera/config/build_scene.h>

#include "test_support.h"

using namespace tessera;
using namespace tessera::config;
using tessera::config::test::config_error;
using tessera::config::test::TempDir;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

/// A render whose annotations block is `lines` (each indented 6 spaces), starting on line 6.
std::string with_annotations(const std::string& lines, int width = 256, int height = 256) {
  return "renders:\n"
         "  - name: heat\n"
         "    camera: {position: [0, 0, 5]}\n"
         "    image: {width: " +
         std::to_string(width) + ", height: " + std::to_string(height) +
         "}\n"
         "    transfer_function: {range: [300, 400], opacity: [[0, 1]]}\n"
         "    annotations:\n" +
         lines;
}

}  // namespace

TEST_CASE("annotations: defaults and every key", "[config][annotations]") {
  const Config a = parse_config(with_annotations("      colorbar: true\n"), "s.yaml", "");
  REQUIRE(a.renders[0].annotations);
  const AnnotationsSpec& s = *a.renders[0].annotations;
  CHECK(s.colorbar);
  CHECK(s.bar.corner == Corner::BottomRight);
  CHECK(s.bar.orientation == BarOrientation::Vertical);
  CHECK(s.bar.length == 0.4);
  CHECK(s.bar.thickness == 0.04);
  CHECK(s.bar.ticks == 5);
  CHECK_FALSE(s.bar.label);
  CHECK(s.text.empty());
  CHECK(s.font == kDefaultFontPath);
  CHECK(s.font_size == 0.03);
  CHECK_FALSE(parse_config(with_annotations("      colorbar: false\n"), "s.yaml", "").renders[0].annotations->colorbar);

  TempDir dir;
  dir.write("head.raw", "");
  const Config full = load_config(dir.write("scene.yaml", test::full_config_yaml()));
  REQUIRE(full.renders[0].annotations);
  const AnnotationsSpec& f = *full.renders[0].annotations;
  CHECK(f.bar.corner == Corner::TopRight);
  CHECK(f.bar.orientation == BarOrientation::Horizontal);
  CHECK(f.bar.length == 0.5);
  CHECK(f.bar.thickness == 0.05);
  CHECK(f.bar.ticks == 4);
  CHECK(*f.bar.label == "T [K]");
  CHECK(f.text_corner == Corner::BottomLeft);
  CHECK(f.title == "Close view");
  CHECK(f.font_size == 0.04);
  CHECK_FALSE(full.renders[1].annotations);
  // Written back and read again: the same
  const std::string text = to_yaml(full);
  const Config b = parse_config(text, "again.yaml", "/");
  CHECK(to_yaml(b) == text);
  CHECK(b.renders[0].annotations->text == f.text);
  CHECK(*b.renders[0].annotations->bar.label == "T [K]");
  CHECK(b.renders[0].annotations->bar.orientation == BarOrientation::Horizontal);
  CHECK(b.renders[0].annotations->bar.corner == Corner::TopRight);
  CHECK(b.renders[0].annotations->font == f.font);
}

TEST_CASE("annotations: text patterns expand like output patterns", "[config][annotations]") {
  CHECK(format_text_pattern("{name}  step {step}  t = {time:.3g}", "heat", 12, 0.00123456) ==
        "heat  step 12  t = 0.00123");
  CHECK(format_text_pattern("{step:06d} {{x}} {time}", "a", 7, 0.1) == "000007 {x} 0.1");
  CHECK(format_text_pattern("a/b .hidden", "a", 0, 0.0) == "a/b .hidden");  // no file-name rules
  CHECK_THROWS_WITH(validate_text_pattern("{rank}"), StartsWith("bad text pattern") && Contains("{rank}"));
  CHECK_THROWS_WITH(validate_text_pattern("{stpe}"), Contains("unknown placeholder {stpe}"));
  CHECK_THROWS_WITH(validate_text_pattern("{step:.3f}"), Contains("is an integer"));
  CHECK_THROWS_WITH(validate_text_pattern("line\nbreak"), Contains("control character"));
}

TEST_CASE("annotations: what the colour bar and the text show", "[config][annotations]") {
  const Config c = parse_config(with_annotations("      colorbar: true\n      text: \"{name} {step}\"\n"
                                                 "      title: T\n"),
                                "s.yaml", "");
  RenderSpec r = c.renders[0];
  r.field = "temperature";
  const TransferFunction tf = build_transfer_function(r.transfer_function, {0.0, 1.0});
  const AnnotationDesc d = build_annotations(*r.annotations, r.name, r.field, tf, 42, 1.5);
  REQUIRE(d.texts.size() == 2u);
  CHECK(d.texts[0].text == "T");  // the title first
  CHECK(d.texts[1].text == "heat 42");
  CHECK(d.bar.label == "temperature");  // no label: the field name
  CHECK(d.tf.lo == 300.0);
  CHECK(d.tf.hi == 400.0);
}

TEST_CASE("annotations: bad values are load-time errors with their position", "[config][annotations]") {
  const auto err = [](const std::string& lines, int w = 256, int h = 256) {
    return config_error(with_annotations(lines, w, h));
  };
  CHECK_THAT(err("      text: \"{name} {rank}\"\n"),
             StartsWith("scene.yaml:7:7: renders[0].annotations.text: bad text pattern") &&
                 Contains("unknown placeholder {rank}"));
  CHECK_THAT(err("      title: \"" + std::string(300, 'x') + "\"\n"),
             StartsWith("scene.yaml:7:7: renders[0].annotations.title:") && Contains("at most 256"));
  CHECK_THAT(err("      colorbar: {length: 0}\n"),
             StartsWith("scene.yaml:7:18: renders[0].annotations.colorbar.length:") && Contains("(0, 1]"));
  CHECK_THAT(err("      colorbar: {thickness: 1.5}\n"), Contains("colorbar.thickness") && Contains("(0, 1]"));
  CHECK_THAT(err("      font_size: -1\n"), Contains("annotations.font_size") && Contains("(0, 1]"));
  CHECK_THAT(err("      colorbar: {corner: middle}\n"),
             Contains("colorbar.corner") && Contains("top-left") && Contains("bottom-right"));
  CHECK_THAT(err("      text_corner: left\n"), Contains("annotations.text_corner"));
  CHECK_THAT(err("      colorbar: {orientation: diagonal}\n"), Contains("vertical") && Contains("horizontal"));
  CHECK_THAT(err("      colorbar: {ticks: 1}\n"), Contains("colorbar.ticks"));
  CHECK_THAT(err("      colour_bar: true\n"), Contains("colour_bar") && Contains("colorbar"));
  CHECK_THAT(err("      colorbar: maybe\n"), Contains("true or false"));
  // A colour bar larger than the image, with its labels
  CHECK_THAT(err("      colorbar: {length: 1}\n"),
             StartsWith("scene.yaml:6:5: renders[0].annotations:") && Contains("the colour bar with its labels needs"));
  CHECK_THAT(err("      colorbar: true\n", 16, 16), Contains("more than the 16x16 image has"));
  CHECK_THAT(err("      text: \"" + std::string(200, 'W') + "\"\n      font_size: 1\n", 64, 64),
             Contains("text 1 needs"));
  // Fonts: a missing file, a file that is no font
  CHECK_THAT(err("      font: /nonexistent/x.ttf\n"), Contains("annotations.font") && Contains("x.ttf"));
  TempDir dir;
  dir.write("fake.ttf", "not a font");
  const std::string fake = config_error(with_annotations("      font: fake.ttf\n"), dir.path().string());
  CHECK_THAT(fake, StartsWith("scene.yaml:7:7: renders[0].annotations.font:") && Contains("cannot load font"));
}

TEST_CASE("annotations: text that is not UTF-8 loads as U+FFFD and writes back as it loaded", "[config][annotations]") {
  // Text, title and label with bytes that are not UTF-8: accepted, each maximal invalid
  // subsequence one U+FFFD (what the picture draws), and the effective config reloads to the
  // same texts; names and paths stay refused (they could not be written back)
  const std::string fffd = "\xEF\xBF\xBD";
  const std::string yaml = with_annotations("      text: \"T \xE2\x82 {step}\"\n"
                                            "      title: caf\xE9\n"
                                            "      colorbar: {label: \"p\xC0\xAF\"}\n");
  const Config c = parse_config(yaml, "s.yaml", "");
  const AnnotationsSpec& a = *c.renders[0].annotations;
  CHECK(a.text == "T " + fffd + " {step}");
  CHECK(a.title == "caf" + fffd);
  REQUIRE(a.bar.label);
  CHECK(*a.bar.label == "p" + fffd + fffd);
  const Config again = parse_config(to_yaml(c), "effective.yaml", "");
  const AnnotationsSpec& b = *again.renders[0].annotations;
  CHECK(b.text == a.text);
  CHECK(b.title == a.title);
  CHECK(b.bar.label == a.bar.label);
  CHECK(to_yaml(again) == to_yaml(c));
  // Expanded for a picture: the replacement characters stay
  const TransferFunction tf = build_transfer_function(c.renders[0].transfer_function, {0.0, 1.0});
  CHECK(build_annotations(a, "heat", "", tf, 7, 0.0).texts[1].text == "T " + fffd + " 7");
  // The byte limit counts the text as loaded (U+FFFD is 3 bytes)
  CHECK_THAT(config_error(with_annotations("      text: \"" + std::string(100, '\xFF') + "\"\n")),
             Contains("annotations.text: text of 300 bytes (100 as written") && Contains("at most 256"));
  CHECK(parse_config(with_annotations("      text: \"" + std::string(85, '\xFF') + "\"\n"), "s.yaml", "")
            .renders[0]
            .annotations->text.size() == 255u);
  // Control characters are still refused
  CHECK_THAT(config_error(with_annotations("      colorbar: {label: \"a\\tb\"}\n")), Contains("control character"));
}
