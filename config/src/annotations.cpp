// From the `annotations:` block to the core description of one picture.
#include <tessera/config/annotations.h>

namespace tessera::config {

AnnotationDesc build_annotations(const AnnotationsSpec& a, const std::string& name, const std::string& field,
                                 const TransferFunction& tf, std::int64_t step, double time) {
  AnnotationDesc d;
  d.font_path = a.font;
  d.font_size = a.font_size;
  // Title first: in a shared corner it stacks above the text
  if (!a.title.empty()) d.texts.push_back({format_text_pattern(a.title, name, step, time), a.title_corner});
  if (!a.text.empty()) d.texts.push_back({format_text_pattern(a.text, name, step, time), a.text_corner});
  d.colorbar = a.colorbar;
  d.bar.corner = a.bar.corner;
  d.bar.orientation = a.bar.orientation;
  d.bar.length = a.bar.length;
  d.bar.thickness = a.bar.thickness;
  d.bar.ticks = a.bar.ticks;
  d.bar.label = a.bar.label ? *a.bar.label : field;
  d.tf = tf;
  return d;
}

}  // namespace tessera::config
