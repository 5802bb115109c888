// `annotations:` of a render: the colour bar and the text lines drawn into the PNG. Every key
// is checked here, and the whole layout is made once with the font, so a font FreeType cannot
// open or a colour bar larger than the image is an error at load time, not at render time.
#include <tessera/config/annotations.h>
#include <tessera/config/build_scene.h>
#include <tessera/config/render_spec.h>

#include "enum_names.h"
#include "parsers.h"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace tessera::config::detail {
namespace {

const Range kFraction{0.0, 1.0, true, false};  // (0, 1]

/// Text to draw, invalid UTF-8 as U+FFFD, at most kMaxAnnotationPattern bytes after that (what
/// the effective config writes back must load again).
std::string drawn_text(const Value& v, const char* what) {
  const std::string t = v.drawn_text(true);
  if (t.size() > kMaxAnnotationPattern) {
    const std::string grown =
        t.size() == v.text().size()
            ? ""
            : " (" + std::to_string(v.text().size()) + " as written, each invalid UTF-8 sequence made U+FFFD, 3 bytes)";
    v.fail(std::string(what) + " of " + std::to_string(t.size()) + " bytes" + grown + " (allowed: at most " +
           std::to_string(kMaxAnnotationPattern) + ")");
  }
  return t;
}

/// A text or title pattern: at most kMaxAnnotationPattern bytes, known placeholders.
std::string pattern(const Value& v) {
  const std::string p = drawn_text(v, "text");
  try {
    validate_text_pattern(p);
  } catch (const std::invalid_argument& e) {
    v.fail(e.what());
  }
  return p;
}

void parse_colorbar(const Value& v, AnnotationsSpec& a) {
  if (!v.is_map()) {
    a.colorbar = v.boolean();
    return;
  }
  const Map m = v.map_with_keys({"corner", "orientation", "length", "thickness", "ticks", "label"});
  a.colorbar = true;
  ColorBarSpec& b = a.bar;
  b.corner = m.choice_or("corner", b.corner, kCornerNames);
  b.orientation = m.choice_or("orientation", b.orientation, kOrientationNames);
  b.length = m.number_or("length", b.length, kFraction);
  b.thickness = m.number_or("thickness", b.thickness, kFraction);
  b.ticks = static_cast<int>(m.integer_or("ticks", b.ticks, 2, 10));
  if (const auto l = m.get("label")) {
    b.label = drawn_text(*l, "label");
    for (const char c : *b.label)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        l->fail("label with a control character (allowed: printable characters, one line)");
  }
}

/// `font:` as given (must exist), else the first default that exists; either way FreeType
/// must open it (checked by the caller).
std::string font_file(const Map& m, const Value& block) {
  if (const auto f = m.get("font")) return resolve_existing_file(*f);
  std::error_code ec;
  if (std::filesystem::is_regular_file(kDefaultFontPath, ec)) return kDefaultFontPath;
  for (const char* path : kFallbackFontPaths)
    if (std::filesystem::is_regular_file(path, ec)) return path;
  block.fail(std::string("no font: DejaVu Sans is not installed (looked for ") + kDefaultFontPath +
             " and where other distributions put it) (allowed: install fonts-dejavu-core, or give font: a "
             "TrueType/OpenType file)");
}

}  // namespace

AnnotationsSpec parse_annotations(const Value& v, const RenderSpec& r) {
  const Map m = v.map_with_keys({"colorbar", "text", "text_corner", "title", "title_corner", "font", "font_size"});
  AnnotationsSpec a;
  if (const auto c = m.get("colorbar")) parse_colorbar(*c, a);
  if (const auto t = m.get("text")) a.text = pattern(*t);
  a.text_corner = m.choice_or("text_corner", a.text_corner, kCornerNames);
  if (const auto t = m.get("title")) a.title = pattern(*t);
  a.title_corner = m.choice_or("title_corner", a.title_corner, kCornerNames);
  a.font_size = m.number_or("font_size", a.font_size, kFraction);
  a.font = font_file(m, v);

  // The font opens, and the layout fits the image: made once here as a picture at step 0,
  // time 0 would be (an automatic range as [0, 1])
  const Value where = m.get("font") ? *m.get("font") : v;
  try {
    const TransferFunction tf = build_transfer_function(r.transfer_function, {0.0, 1.0});
    const AnnotationDesc d = build_annotations(a, r.name, r.field, tf, 0, 0.0);
    const AnnotationLayout layout = layout_annotations(r.image.width, r.image.height, d);
    std::string why;
    if (!annotations_fit(r.image.width, r.image.height, layout, &why))
      v.fail(why + " (allowed: a smaller colorbar length or thickness, font_size or text, or a larger image)");
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const ConfigError*>(&e)) throw;
    where.fail(e.what());
  } catch (const std::invalid_argument& e) {
    v.fail(e.what());
  }
  return a;
}

}  // namespace tessera::config::detail
