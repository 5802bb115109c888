// Annotations: layout of texts and the colour bar in the image corners, and their drawing
// into the 8-bit picture.
#include <tessera/annotate.h>
#include <tessera/image_io.h>
#include <tessera/number_text.h>

#include "annotate/font.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tessera {
namespace {

using annotate::Font;
using annotate::TextMask;

/// The outline around glyphs grows with the font up to this many pixels: wide enough to read
/// at any size, and the dilation's cost per pixel stays bounded.
constexpr int kMaxOutline = 5;

/// Sizes derived from the font size, all in pixels.
struct Metrics {
  int font = 0;     ///< em size
  int margin = 0;   ///< from the image edge to a box
  int pad = 0;      ///< inside a box, around its content
  int gap = 0;      ///< between boxes, and between a bar and its labels
  int outline = 0;  ///< outline radius around glyphs
  explicit Metrics(int px)
      : font(px),
        margin(std::max(4, px / 2)),
        pad(std::max(3, px / 3)),
        gap(std::max(2, px / 4)),
        outline(std::clamp(px / 14, 1, kMaxOutline)) {}
};

struct PlacedText {
  TextMask mask;
  int x = 0, y = 0;  ///< top-left of the mask in the image
};

/// Everything drawn: boxes, text masks at their places, the bar and its ticks.
struct Plan {
  AnnotationLayout layout;
  std::vector<PlacedText> texts;  ///< item texts, bar label and tick labels
  std::vector<PixelBox> tick_marks;
};

/// An item before placement: its box size and content relative to the box's top-left.
struct Item {
  Corner corner = Corner::TopLeft;
  int w = 0, h = 0;
  std::vector<PlacedText> texts;           ///< relative
  PixelBox bar, color_band, opacity_band;  ///< relative; empty for a text
  std::vector<PixelBox> marks;             ///< relative
  std::vector<PixelBox> labels;            ///< relative: the tick labels' masks
  bool is_bar = false;
};

PixelBox shifted(PixelBox b, int dx, int dy) { return {b.x0 + dx, b.y0 + dy, b.x1 + dx, b.y1 + dy}; }

Item text_item(const Font& font, const Metrics& m, const AnnotationText& t, int width) {
  Item it;
  it.corner = t.corner;
  PlacedText p;
  p.mask = font.render(t.text, std::max(1, width - 2 * m.margin - 2 * m.pad));
  p.x = m.pad;
  p.y = m.pad;
  it.w = p.mask.width + 2 * m.pad;
  it.h = p.mask.height + 2 * m.pad;
  it.texts.push_back(std::move(p));
  return it;
}

Item bar_item(const Font& font, const Metrics& m, const AnnotationDesc& d, int width, int height) {
  const ColorBarDesc& b = d.bar;
  const bool vertical = b.orientation == BarOrientation::Vertical;
  const int length = std::max(2, static_cast<int>(std::lround(b.length * (vertical ? height : width))));
  const int thick = std::max(4, static_cast<int>(std::lround(b.thickness * std::min(width, height))));
  const int tick = std::max(2, thick / 4);
  const int line = font.line_height();

  const auto along = [&](double v) {  // pixel index along the bar of a data value
    // Halves where the range's width overflows (a range of +-1e308)
    const double lo = d.tf.lo, hi = d.tf.hi;
    const double u = std::isfinite(hi - lo) ? (v - lo) / (hi - lo) : (0.5 * v - 0.5 * lo) / (0.5 * hi - 0.5 * lo);
    return static_cast<int>(std::lround(std::clamp(u, 0.0, 1.0) * (length - 1)));
  };

  // Tick labels, measured; fewer ticks while neighbouring labels would touch (a short bar):
  // nice ticks for targets down to 2, then the range's two ends, then its first value alone
  std::vector<double> values;
  std::vector<TextMask> labels;
  int label_w = 0;
  for (int target = b.ticks; target >= 0; --target) {
    values = target >= 2   ? colorbar_ticks(d.tf.lo, d.tf.hi, target)
             : target == 1 ? std::vector<double>{d.tf.lo, d.tf.hi}
                           : std::vector<double>{d.tf.lo};
    labels.clear();
    label_w = 0;
    for (const std::string& text : colorbar_labels(values, d.tf.lo, d.tf.hi)) {
      labels.push_back(font.render(text, width));
      label_w = std::max(label_w, labels.back().width);
    }
    bool crowded = false;
    for (std::size_t i = 1; i < values.size(); ++i) {
      const int need = vertical ? line : (labels[i - 1].width + labels[i].width) / 2 + m.gap;
      crowded = crowded || along(values[i]) - along(values[i - 1]) < need;
    }
    if (!crowded) break;
  }
  TextMask title = font.render(b.label, std::max(1, width - 2 * m.margin - 2 * m.pad));
  const int title_h = b.label.empty() ? 0 : line + m.gap;

  Item it;
  it.corner = b.corner;
  it.is_bar = true;
  if (vertical) {
    const int x0 = m.pad, y0 = m.pad + title_h + line / 2;
    it.bar = {x0, y0, x0 + thick, y0 + length};
    it.color_band = {x0, y0, x0 + thick / 2, y0 + length};
    it.opacity_band = {x0 + thick / 2, y0, x0 + thick, y0 + length};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const int y = y0 + length - 1 - along(values[i]);
      it.marks.push_back({x0 + thick, y, x0 + thick + tick, y + 1});
      PlacedText p{std::move(labels[i]), x0 + thick + tick + m.gap, y - line / 2};
      it.labels.push_back({p.x, p.y, p.x + p.mask.width, p.y + p.mask.height});
      it.texts.push_back(std::move(p));
    }
    it.w = std::max(thick + tick + m.gap + label_w, title.width) + 2 * m.pad;
    it.h = title_h + line + length + 2 * m.pad;
  } else {
    const int x0 = m.pad + label_w / 2, y0 = m.pad + title_h;
    it.bar = {x0, y0, x0 + length, y0 + thick};
    it.color_band = {x0, y0, x0 + length, y0 + thick / 2};
    it.opacity_band = {x0, y0 + thick / 2, x0 + length, y0 + thick};
    for (std::size_t i = 0; i < values.size(); ++i) {
      const int x = x0 + along(values[i]);
      it.marks.push_back({x, y0 + thick, x + 1, y0 + thick + tick});
      const int lw = labels[i].width;
      PlacedText p{std::move(labels[i]), x - lw / 2, y0 + thick + tick + m.gap};
      it.labels.push_back({p.x, p.y, p.x + p.mask.width, p.y + p.mask.height});
      it.texts.push_back(std::move(p));
    }
    it.w = std::max(length + label_w, title.width) + 2 * m.pad;
    it.h = title_h + thick + tick + m.gap + line + 2 * m.pad;
  }
  if (!b.label.empty()) it.texts.push_back(PlacedText{std::move(title), m.pad, m.pad});
  return it;
}

Plan plan(int width, int height, const AnnotationDesc& d, const Font& font, const Metrics& m) {
  std::vector<Item> items;
  for (const AnnotationText& t : d.texts)
    if (!t.text.empty()) items.push_back(text_item(font, m, t, width));
  if (d.colorbar) items.push_back(bar_item(font, m, d, width, height));

  // Stack the items of each corner: from the top for top corners, ending at the bottom
  // margin for bottom corners; first item on top either way
  Plan p;
  p.layout.font_pixels = m.font;
  p.layout.boxes.resize(items.size());
  for (const Corner c : {Corner::TopLeft, Corner::TopRight, Corner::BottomLeft, Corner::BottomRight}) {
    const bool top = c == Corner::TopLeft || c == Corner::TopRight;
    const bool left = c == Corner::TopLeft || c == Corner::BottomLeft;
    int total = 0, count = 0;
    for (const Item& it : items)
      if (it.corner == c) total += it.h + (count++ ? m.gap : 0);
    int y = top ? m.margin : height - m.margin - total;
    for (std::size_t i = 0; i < items.size(); ++i) {
      Item& it = items[i];
      if (it.corner != c) continue;
      const int x = left ? m.margin : width - m.margin - it.w;
      p.layout.boxes[i] = {x, y, x + it.w, y + it.h};
      for (PlacedText& t : it.texts) p.texts.push_back({std::move(t.mask), t.x + x, t.y + y});
      for (const PixelBox& mk : it.marks) p.tick_marks.push_back(shifted(mk, x, y));
      for (const PixelBox& lb : it.labels) p.layout.tick_labels.push_back(shifted(lb, x, y));
      if (it.is_bar) {
        p.layout.bar = shifted(it.bar, x, y);
        p.layout.color_band = shifted(it.color_band, x, y);
        p.layout.opacity_band = shifted(it.opacity_band, x, y);
      }
      y += it.h + m.gap;
    }
  }
  return p;
}

int font_pixels(int width, int height, double font_size) {
  const double px = std::round(font_size * std::min(width, height));
  return static_cast<int>(std::clamp(px, static_cast<double>(kMinFontPixels), static_cast<double>(kMaxFontPixels)));
}

/// Pixels of the picture, blended with straight alpha, clipped to the image.
struct Canvas {
  int width, height;
  std::uint8_t* rgba;
  void blend(int x, int y, const double rgb[3], double a) {
    if (x < 0 || y < 0 || x >= width || y >= height || !(a > 0.0)) return;
    a = std::min(a, 1.0);
    std::uint8_t* p = rgba + (static_cast<std::size_t>(y) * width + x) * 4;
    // Rounded to nearest (the values are in [0, 255], so + 0.5 and truncation does it)
    for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(p[c] * (1.0 - a) + rgb[c] * 255.0 * a + 0.5);
    p[3] = static_cast<std::uint8_t>(255.0 * a + p[3] * (1.0 - a) + 0.5);
  }
  void fill(const PixelBox& b, const double rgb[3], double a) {
    for (int y = std::max(0, b.y0); y < std::min(height, b.y1); ++y)
      for (int x = std::max(0, b.x0); x < std::min(width, b.x1); ++x) blend(x, y, rgb, a);
  }
};

/// Glyph coverage grown by r pixels (a square max filter, separable): the outline.
std::vector<std::uint8_t> dilate(const TextMask& t, int r, int& w, int& h) {
  w = t.width + 2 * r;
  h = t.height + 2 * r;
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(w) * t.height, 0), out(static_cast<std::size_t>(w) * h, 0);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const std::uint8_t v = t.coverage[static_cast<std::size_t>(y) * t.width + x];
      if (!v) continue;
      for (int k = 0; k <= 2 * r; ++k) {
        std::uint8_t& d = rows[static_cast<std::size_t>(y) * w + x + k];
        d = std::max(d, v);
      }
    }
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t v = rows[static_cast<std::size_t>(y) * w + x];
      if (!v) continue;
      for (int k = 0; k <= 2 * r; ++k) {
        std::uint8_t& d = out[static_cast<std::size_t>(y + k) * w + x];
        d = std::max(d, v);
      }
    }
  return out;
}

void draw_text(Canvas& cv, const PlacedText& t, int outline) {
  static constexpr double kBlack[3] = {0.0, 0.0, 0.0}, kWhite[3] = {1.0, 1.0, 1.0};
  int w = 0, h = 0;
  const std::vector<std::uint8_t> grown = dilate(t.mask, outline, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      cv.blend(t.x - outline + x, t.y - outline + y, kBlack, 0.85 * grown[static_cast<std::size_t>(y) * w + x] / 255.0);
  for (int y = 0; y < t.mask.height; ++y)
    for (int x = 0; x < t.mask.width; ++x)
      cv.blend(t.x + x, t.y + y, kWhite, t.mask.coverage[static_cast<std::size_t>(y) * t.mask.width + x] / 255.0);
}

/// The two bands of the bar, the frame around it and its tick marks.
void draw_bar(Canvas& cv, const AnnotationDesc& d, const Plan& p) {
  const AnnotationLayout& l = p.layout;
  const bool vertical = d.bar.orientation == BarOrientation::Vertical;
  const int length = vertical ? l.bar.y1 - l.bar.y0 : l.bar.x1 - l.bar.x0;
  const int thick = vertical ? l.bar.x1 - l.bar.x0 : l.bar.y1 - l.bar.y0;
  const double max_opacity = d.tf.opacity.max_value();
  const int cell = std::max(2, thick / 4);
  const ToneMap srgb{0.0, ToneMap::Curve::Clamp};
  for (int i = 0; i < length; ++i) {
    const double u = length > 1 ? static_cast<double>(i) / (length - 1) : 0.0;
    const Color c = d.tf.diffuse.eval(u);
    const double rgb[3] = {tonemap_channel(c.x, srgb), tonemap_channel(c.y, srgb), tonemap_channel(c.z, srgb)};
    const double a = max_opacity > 0.0 ? std::clamp(d.tf.opacity.eval(u) / max_opacity, 0.0, 1.0) : 0.0;
    for (int k = 0; k < thick; ++k) {
      const int x = vertical ? l.bar.x0 + k : l.bar.x0 + i;
      const int y = vertical ? l.bar.y1 - 1 - i : l.bar.y0 + k;
      if (l.color_band.contains(x, y)) {
        cv.blend(x, y, rgb, 1.0);
        continue;
      }
      const bool light = (((x - l.opacity_band.x0) / cell) + ((y - l.opacity_band.y0) / cell)) % 2 == 0;
      const double grey[3] = {light ? 0.8 : 0.55, light ? 0.8 : 0.55, light ? 0.8 : 0.55};
      cv.blend(x, y, grey, 1.0);
      cv.blend(x, y, rgb, a);
    }
  }
  static constexpr double kFrame[3] = {0.85, 0.85, 0.85};
  const PixelBox& b = l.bar;
  cv.fill({b.x0 - 1, b.y0 - 1, b.x1 + 1, b.y0}, kFrame, 1.0);
  cv.fill({b.x0 - 1, b.y1, b.x1 + 1, b.y1 + 1}, kFrame, 1.0);
  cv.fill({b.x0 - 1, b.y0, b.x0, b.y1}, kFrame, 1.0);
  cv.fill({b.x1, b.y0, b.x1 + 1, b.y1}, kFrame, 1.0);
  for (const PixelBox& mk : p.tick_marks) cv.fill(mk, kFrame, 1.0);
}

void check_fraction(double v, const char* what) {
  if (!(v > 0.0 && v <= 1.0))
    throw std::invalid_argument(std::string("annotations: ") + what + " " + short_number(v) +
                                " is out of range (allowed: (0, 1], a fraction of the image)");
}

}  // namespace

void validate_annotations(const AnnotationDesc& d) {
  check_fraction(d.font_size, "font_size");
  if (d.texts.size() > kMaxAnnotationTexts)
    throw std::invalid_argument("annotations: " + std::to_string(d.texts.size()) + " texts (allowed: at most " +
                                std::to_string(kMaxAnnotationTexts) + ")");
  if (d.colorbar) {
    check_fraction(d.bar.length, "colorbar length");
    check_fraction(d.bar.thickness, "colorbar thickness");
    if (d.bar.ticks < 2 || d.bar.ticks > 10)
      throw std::invalid_argument("annotations: colorbar ticks " + std::to_string(d.bar.ticks) +
                                  " is out of range (allowed: 2 to 10)");
    if (!(d.tf.lo < d.tf.hi) || !std::isfinite(d.tf.lo) || !std::isfinite(d.tf.hi))
      throw std::invalid_argument("annotations: colorbar range [" + short_number(d.tf.lo) + ", " +
                                  short_number(d.tf.hi) + "] is empty (allowed: finite lo < hi)");
  }
  Font font(d.font_path);
}

AnnotationLayout layout_annotations(int width, int height, const AnnotationDesc& d) {
  validate_annotations(d);
  Font font(d.font_path);
  const Metrics m(font_pixels(width, height, d.font_size));
  font.set_pixel_size(m.font);
  return plan(width, height, d, font, m).layout;
}

bool annotations_fit(int width, int height, const AnnotationLayout& layout, std::string* why) {
  const std::size_t bar_index = layout.bar.empty() ? layout.boxes.size() : layout.boxes.size() - 1;
  for (std::size_t i = 0; i < layout.boxes.size(); ++i) {
    const PixelBox& b = layout.boxes[i];
    if (b.x0 >= 0 && b.y0 >= 0 && b.x1 <= width && b.y1 <= height) continue;
    if (why) {
      *why = (i == bar_index ? std::string("the colour bar with its labels") : "text " + std::to_string(i + 1)) +
             " needs " + std::to_string(b.x1 - b.x0) + "x" + std::to_string(b.y1 - b.y0) +
             " pixels and the margins around it, more than the " + std::to_string(width) + "x" +
             std::to_string(height) + " image has";
    }
    return false;
  }
  return true;
}

void draw_annotations(int width, int height, std::uint8_t* rgba8, const AnnotationDesc& d) {
  validate_annotations(d);
  if (width <= 0 || height <= 0 || !rgba8) return;
  Font font(d.font_path);
  const Metrics m(font_pixels(width, height, d.font_size));
  font.set_pixel_size(m.font);
  const Plan p = plan(width, height, d, font, m);

  // Backings first, then the bar and the texts on them
  Canvas cv{width, height, rgba8};
  static constexpr double kBacking[3] = {0.0, 0.0, 0.0};
  for (const PixelBox& b : p.layout.boxes) cv.fill(b, kBacking, 0.55);
  if (d.colorbar) draw_bar(cv, d, p);
  for (const PlacedText& t : p.texts) draw_text(cv, t, m.outline);
}

}  // namespace tessera
