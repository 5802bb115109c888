// Annotations in the 8-bit picture: where they are drawn (corners, boxes, nothing outside
// them), what the colour bar shows (the TF's diffuse colours from first to last, opacity as
// alpha), tick values and labels, sizes at 256 and 2048 pixels, bounded text, and that the
// PNG changes only inside the boxes while the EXR stays the same bytes.
#include <tessera/annotate.h>
#include <tessera/image_format.h>
#include <tessera/image_io.h>
#include <tessera/message_text.h>

#include <catch2/catch.hpp>

#include "read_png.h"
#include "temp_dir.h"

#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

using namespace tessera;
using Catch::Matchers::Contains;
using tessera_test::read_png_rgba;

namespace {

constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// A TF from red to blue (diffuse), opacity `op0` at the first value to `op1` at the last.
TransferFunction red_to_blue(double lo, double hi, double op0 = 1.0, double op1 = 1.0) {
  TransferFunction tf;
  tf.lo = lo;
  tf.hi = hi;
  tf.diffuse = ColorTF({0.0, 1.0}, {Color(1.0, 0.0, 0.0), Color(0.0, 0.0, 1.0)});
  tf.opacity = ScalarTF({0.0, 1.0}, {op0, op1});
  return tf;
}

AnnotationDesc desc_with(Corner corner, BarOrientation orientation) {
  AnnotationDesc d;
  d.font_path = kFont;
  d.texts = {{"Heat  step 12  t = 0.5", corner}};
  d.colorbar = true;
  d.bar.corner = corner;
  d.bar.orientation = orientation;
  d.bar.label = "temperature";
  d.tf = red_to_blue(300.0, 400.0);
  return d;
}

/// A picture with a smooth pattern, so that any change shows.
std::vector<std::uint8_t> pattern(int w, int h) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &px[(static_cast<std::size_t>(y) * w + x) * 4];
      p[0] = static_cast<std::uint8_t>((x * 7) & 255);
      p[1] = static_cast<std::uint8_t>((y * 5) & 255);
      p[2] = static_cast<std::uint8_t>(((x + y) * 3) & 255);
      p[3] = 255;
    }
  return px;
}

const std::uint8_t* at(const std::vector<std::uint8_t>& px, int w, int x, int y) {
  return &px[(static_cast<std::size_t>(y) * w + x) * 4];
}

bool same_pixel(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int w, int x, int y) {
  return std::equal(at(a, w, x, y), at(a, w, x, y) + 4, at(b, w, x, y));
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("colour bar ticks are nice numbers inside the range", "[annotate]") {
  CHECK(colorbar_ticks(0.0, 1.0, 5) == std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0});
  const std::vector<double> t = colorbar_ticks(300.0, 400.0, 5);
  CHECK(t == std::vector<double>{300.0, 320.0, 340.0, 360.0, 380.0, 400.0});
  // An offset range: ticks at multiples of the step, never outside
  for (const double v : colorbar_ticks(-0.37, 2.61, 5)) {
    CHECK(v >= -0.37);
    CHECK(v <= 2.61);
    CHECK(std::abs(v / 0.5 - std::round(v / 0.5)) < 1e-9);
  }
  // A range too narrow for its magnitude: its two ends
  CHECK(colorbar_ticks(1e15, 1e15 + 1.0, 5) == std::vector<double>{1e15, 1e15 + 1.0});
  for (int target = 2; target <= 10; ++target) {
    const auto ticks = colorbar_ticks(-3.0, 7.0, target);
    CHECK(ticks.size() >= 2u);
    CHECK(ticks.size() <= static_cast<std::size_t>(2 * target + 2));
  }
}

TEST_CASE("tick labels round to the step and never show -0", "[annotate]") {
  CHECK(tick_label(0.6000000000000001, 0.2, 1.0) == "0.6");
  CHECK(tick_label(320.0, 20.0, 400.0) == "320");
  CHECK(tick_label(-1e-17, 0.2, 1.0) == "0.0");
  CHECK(tick_label(-0.0, 0.5, 1.0) == "0.0");
  CHECK(tick_label(-0.0, 50.0, 100.0) == "0");
  CHECK(tick_label(0.05, 0.05, 0.2) == "0.05");
  CHECK(tick_label(1.5e6, 5e5, 3e6) == "1.5e+06");
  CHECK(tick_label(2e-5, 1e-5, 1e-4) == "2.0e-05");
}

namespace {

/// Whether `label` reads as `tick` to within half a unit in its last digit: "101324.6",
/// "1.5e+06", or a base and an offset, "1e+16 + 2", whose unit is the offset's.
bool true_to(const std::string& label, double tick) {
  long double value = 0.0L;
  std::string last = label;
  const std::size_t plus = label.find(" + "), minus = label.find(" - ");
  const std::size_t op = std::min(plus, minus);
  if (op != std::string::npos) {
    last = label.substr(op + 3);
    const long double base = std::strtold(label.substr(0, op).c_str(), nullptr);
    const long double offset = std::strtold(last.c_str(), nullptr);
    value = op == plus ? base + offset : base - offset;
  } else {
    value = std::strtold(label.c_str(), nullptr);
  }
  // The unit of the last digit: the mantissa's decimals against the exponent
  const std::size_t e = last.find('e');
  const std::string mantissa = last.substr(0, e);
  const std::size_t point = mantissa.find('.');
  const int decimals = point == std::string::npos ? 0 : static_cast<int>(mantissa.size() - point - 1);
  const int exponent = e == std::string::npos ? 0 : std::atoi(last.c_str() + e + 1);
  const long double unit = std::pow(10.0L, static_cast<long double>(exponent - decimals));
  const long double t = tick;
  const long double slack = 8.0L * std::numeric_limits<long double>::epsilon() * std::fabs(t);
  return std::fabs(value - t) <= 0.5L * unit * (1.0L + 1e-9L) + slack;
}

/// Ticks and labels of [lo, hi] at every target, the two ends and the first value alone:
/// ticks ascending inside the range, labels distinct from their neighbours and true.
void check_labels(double lo, double hi) {
  INFO("range [" << std::hexfloat << lo << ", " << hi << "] = [" << std::defaultfloat << std::setprecision(17) << lo
                 << ", " << hi << "]");
  std::vector<std::vector<double>> sets;
  for (int target = 2; target <= 10; ++target) sets.push_back(colorbar_ticks(lo, hi, target));
  sets.push_back({lo, hi});
  for (const std::vector<double>& ticks : sets) {
    REQUIRE(ticks.size() >= 2u);
    const std::vector<std::string> labels = colorbar_labels(ticks, lo, hi);
    REQUIRE(labels.size() == ticks.size());
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      INFO("tick " << ticks[i] << " label \"" << labels[i] << "\"");
      CHECK(ticks[i] >= lo);
      CHECK(ticks[i] <= hi);
      CHECK(true_to(labels[i], ticks[i]));
      CHECK(labels[i].size() <= 48u);
      if (i > 0) {
        CHECK(ticks[i] > ticks[i - 1]);
        CHECK(labels[i] != labels[i - 1]);
      }
    }
  }
  const std::vector<std::string> one = colorbar_labels({lo}, lo, hi);
  REQUIRE(one.size() == 1u);
  INFO("single label \"" << one[0] << "\"");
  CHECK(true_to(one[0], lo));
  CHECK(one[0].size() <= 12u);
}

}  // namespace

TEST_CASE("colour-bar labels differ from their neighbours and round to their ticks at every range", "[annotate]") {
  // The examples of issue 40: a pressure, values near 1e6 and 1e16 with tiny spans
  const auto labels_of = [](double lo, double hi, int target) {
    return colorbar_labels(colorbar_ticks(lo, hi, target), lo, hi);
  };
  CHECK(labels_of(101324.95, 101325.05, 10) ==
        std::vector<std::string>{"101324.95", "101324.96", "101324.97", "101324.98", "101324.99", "101325.00",
                                 "101325.01", "101325.02", "101325.03", "101325.04", "101325.05"});
  CHECK(labels_of(1e6 - 0.5, 1e6 + 0.5, 5) ==
        std::vector<std::string>{"999999.6", "999999.8", "1000000.0", "1000000.2", "1000000.4"});
  CHECK(labels_of(1e16, 1e16 + 10.0, 5) == std::vector<std::string>{"1e+16", "1e+16 + 10"});
  CHECK(labels_of(1e6 - 1e-4, 1e6 + 1e-4, 5) ==
        std::vector<std::string>{"1e+06 - 1.0e-04", "1e+06 - 5e-05", "1e+06", "1e+06 + 5e-05"});
  CHECK(labels_of(-1e16 - 10.0, -1e16, 5) == std::vector<std::string>{"-1e+16 - 10", "-1e+16"});
  // Ranges as before keep their labels
  CHECK(labels_of(0.0, 1.0, 5) == std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"});
  CHECK(labels_of(300.0, 400.0, 5) == std::vector<std::string>{"300", "320", "340", "360", "380", "400"});
  CHECK(labels_of(0.0, 3e6, 5) ==
        std::vector<std::string>{"0", "5.0e+05", "1.0e+06", "1.5e+06", "2.0e+06", "2.5e+06", "3.0e+06"});

  // Extremes: a few ulps wide at every magnitude, huge, tiny, denormal, across zero, overflowing
  const double big = std::numeric_limits<double>::max(), tiny = std::numeric_limits<double>::denorm_min();
  const auto up = [](double v, int ulps) {
    for (int i = 0; i < ulps; ++i) v = std::nextafter(v, HUGE_VAL);
    return v;
  };
  for (const double v :
       {1.0, 0.1, 101325.0, 1e6, 1e15, 1e16, 1e300, -1e300, -1e-300, DBL_MIN, 2.5e-320, big / 2, -big, 7.0, -3.0e-7}) {
    for (const int ulps : {1, 2, 3, 7, 100, 1000000})
      if (std::isfinite(up(v, ulps))) check_labels(v, up(v, ulps));
  }
  const double ranges[][2] = {{-big, big},
                              {-big, 0.0},
                              {0.0, big},
                              {big / 2, big},
                              {-big, -big / 2},
                              {0.0, tiny},
                              {-tiny, tiny},
                              {tiny, 2 * tiny},
                              {1e-310, 1.00001e-310},
                              {0.95, 1.05},
                              {-1.0, 1.0},
                              {1.0 - 1e-15, 1.0},
                              {1e-300, 2e-300},
                              {-1e-5, 1e-5},
                              {101324.5, 101325.5},
                              {-101325.5, -101324.5},
                              {1e16 - 2.0, 1e16},
                              {999999.9999, 1000000.0001},
                              {-1234.5, 98765.4}};
  for (const auto& r : ranges) check_labels(r[0], r[1]);

  // Random ranges (seed 40): magnitudes 1e-320 to 1e300, widths from a few ulps to 1e3 times
  // the magnitude, either sign
  std::mt19937_64 rng(40);
  std::uniform_real_distribution<double> exponent(-320.0, 300.0), width(-17.0, 3.0), unit(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const double lo = (unit(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng)) * (1.0 + unit(rng));
    double hi = lo + std::abs(lo) * std::pow(10.0, width(rng));
    if (!(hi > lo)) hi = up(lo, 1 + static_cast<int>(unit(rng) * 5));
    if (!std::isfinite(hi)) continue;
    check_labels(lo, hi);
  }
}

TEST_CASE("colour bar runs from the TF's first to last diffuse colour, opacity as alpha", "[annotate]") {
  for (const BarOrientation o : {BarOrientation::Vertical, BarOrientation::Horizontal}) {
    const int w = 320, h = 256;
    AnnotationDesc d = desc_with(Corner::BottomRight, o);
    d.texts.clear();
    d.tf = red_to_blue(0.0, 10.0, 0.0, 2.0);  // opacity 0 at lo up to its maximum at hi
    std::vector<std::uint8_t> px = pattern(w, h);
    draw_annotations(w, h, px.data(), d);
    const AnnotationLayout l = layout_annotations(w, h, d);
    REQUIRE(!l.color_band.empty());
    const bool vertical = o == BarOrientation::Vertical;
    const int length = vertical ? l.bar.y1 - l.bar.y0 : l.bar.x1 - l.bar.x0;
    CHECK(length == static_cast<int>(std::lround(0.4 * (vertical ? h : w))));
    // Along the colour band, first value (bottom / left) to last (top / right)
    const auto color_at = [&](int i) {
      const int x = vertical ? l.color_band.x0 : l.color_band.x0 + i;
      const int y = vertical ? l.color_band.y1 - 1 - i : l.color_band.y0;
      return at(px, w, x, y);
    };
    const std::uint8_t* first = color_at(0);
    const std::uint8_t* last = color_at(length - 1);
    CHECK((int(first[0]) == 255 && int(first[1]) == 0 && int(first[2]) == 0));
    CHECK((int(last[0]) == 0 && int(last[1]) == 0 && int(last[2]) == 255));
    for (int i = 1; i < length; ++i) {
      CHECK(color_at(i)[0] <= color_at(i - 1)[0]);
      CHECK(color_at(i)[2] >= color_at(i - 1)[2]);
    }
    // Opacity band: the checker alone where opacity is 0, the plain colour at the maximum
    const int ox = vertical ? l.opacity_band.x0 : l.opacity_band.x0;
    const int oy_lo = vertical ? l.opacity_band.y1 - 1 : l.opacity_band.y0;
    const std::uint8_t* lo = vertical ? at(px, w, ox, oy_lo) : at(px, w, l.opacity_band.x0, l.opacity_band.y0);
    CHECK(int(lo[0]) == int(lo[1]));
    CHECK(int(lo[1]) == int(lo[2]));
    const std::uint8_t* hi = vertical ? at(px, w, ox, l.opacity_band.y0) : at(px, w, l.opacity_band.x1 - 1, oy_lo);
    CHECK((int(hi[0]) == 0 && int(hi[1]) == 0 && int(hi[2]) == 255));
  }
}

TEST_CASE("annotations change pixels only inside their boxes, in the configured corner", "[annotate]") {
  for (const int size : {256, 2048}) {
    for (const Corner c : {Corner::TopLeft, Corner::TopRight, Corner::BottomLeft, Corner::BottomRight}) {
      for (const BarOrientation o : {BarOrientation::Vertical, BarOrientation::Horizontal}) {
        const int w = size, h = size * 3 / 4;
        const AnnotationDesc d = desc_with(c, o);
        const std::vector<std::uint8_t> bare = pattern(w, h);
        std::vector<std::uint8_t> px = bare;
        draw_annotations(w, h, px.data(), d);
        const AnnotationLayout l = layout_annotations(w, h, d);
        REQUIRE(l.boxes.size() == 2u);
        REQUIRE(annotations_fit(w, h, l));
        // The font scales with the image, never below the minimum
        CHECK(l.font_pixels == std::max(kMinFontPixels, static_cast<int>(std::lround(0.03 * h))));
        // The stack sits in its corner, a margin from both edges, and every box has changed pixels
        const bool left = c == Corner::TopLeft || c == Corner::BottomLeft;
        const bool top = c == Corner::TopLeft || c == Corner::TopRight;
        const int margin = std::max(4, l.font_pixels / 2);
        CHECK((top ? l.boxes.front().y0 : h - l.boxes.back().y1) == margin);
        CHECK(l.boxes.front().y1 <= l.boxes.back().y0);  // the text above the bar
        for (const PixelBox& b : l.boxes) {
          CHECK((left ? b.x0 : w - b.x1) == margin);
          int changed = 0;
          for (int y = b.y0; y < b.y1; ++y)
            for (int x = b.x0; x < b.x1; ++x) changed += !same_pixel(px, bare, w, x, y);
          CHECK(changed > (b.x1 - b.x0) * (b.y1 - b.y0) / 2);
        }
        // Text box: at least one line of the font high
        CHECK(l.boxes[0].y1 - l.boxes[0].y0 >= l.font_pixels);
        // Nothing outside the boxes changed
        long outside_changed = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            bool inside = false;
            for (const PixelBox& b : l.boxes) inside = inside || b.contains(x, y);
            if (!inside) outside_changed += !same_pixel(px, bare, w, x, y);
          }
        CHECK(outside_changed == 0);
      }
    }
  }
}

TEST_CASE("tick labels never overlap, on short bars fewer of them", "[annotate]") {
  for (const int size : {256, 2048})
    for (const BarOrientation o : {BarOrientation::Vertical, BarOrientation::Horizontal})
      for (const double length : {0.1, 0.25, 0.4, 1.0}) {
        AnnotationDesc d = desc_with(Corner::BottomLeft, o);
        d.texts.clear();
        d.bar.length = length;
        d.bar.ticks = 10;
        d.tf = red_to_blue(-1234.5, 98765.4);
        const AnnotationLayout l = layout_annotations(size, size, d);
        INFO("size " << size << ", length " << length);
        // A bar too short for two labels keeps one; longer bars keep more
        CHECK(l.tick_labels.size() >= (length < 0.2 ? 1u : 2u));
        if (size == 2048 && length >= 0.4 && o == BarOrientation::Vertical) CHECK(l.tick_labels.size() >= 5u);
        for (std::size_t i = 1; i < l.tick_labels.size(); ++i) {
          const PixelBox& a = l.tick_labels[i - 1];
          const PixelBox& b = l.tick_labels[i];
          const bool apart = a.x1 <= b.x0 || b.x1 <= a.x0 || a.y1 <= b.y0 || b.y1 <= a.y0;
          CHECK(apart);
        }
      }
}

TEST_CASE("text items in one corner stack without overlapping", "[annotate]") {
  AnnotationDesc d;
  d.font_path = kFont;
  d.texts = {{"Title", Corner::TopLeft}, {"step 3", Corner::TopLeft}, {"other", Corner::BottomLeft}};
  d.colorbar = true;
  d.bar.corner = Corner::TopLeft;
  d.tf = red_to_blue(0.0, 1.0);
  const AnnotationLayout l = layout_annotations(512, 512, d);
  REQUIRE(l.boxes.size() == 4u);
  CHECK(l.boxes[0].y1 <= l.boxes[1].y0);
  CHECK(l.boxes[1].y1 <= l.boxes[3].y0);  // the bar after the texts
  CHECK(l.boxes[2].y1 == 512 - std::max(4, l.font_pixels / 2));
}

TEST_CASE("runaway text is cut at the glyph cap and the image width, in bounded time", "[annotate]") {
  AnnotationDesc d;
  d.font_path = kFont;
  d.texts = {{std::string(100000, 'W'), Corner::TopLeft}, {"\xff\xfe bad \xc3 utf-8 \xe2\x82", Corner::BottomLeft}};
  const int w = 2048, h = 256;
  std::vector<std::uint8_t> px = pattern(w, h);
  const auto t0 = std::chrono::steady_clock::now();
  draw_annotations(w, h, px.data(), d);
  const AnnotationLayout l = layout_annotations(w, h, d);
  CHECK(l.boxes[0].x1 <= w);
  CHECK(annotations_fit(w, h, l));
  // The largest font size: capped in pixels
  d.texts = {{"W", Corner::TopLeft}};
  d.font_size = 1.0;
  std::vector<std::uint8_t> big = pattern(2048, 2048);
  draw_annotations(2048, 2048, big.data(), d);
  CHECK(layout_annotations(2048, 2048, d).font_pixels == kMaxFontPixels);
  // Not a timing assertion: a generous bound that only an unbounded loop would pass
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60));
}

TEST_CASE("text that is not UTF-8 draws one visible U+FFFD per maximal invalid subsequence", "[annotate]") {
  const std::string fffd = "\xEF\xBF\xBD";
  // Unicode's maximal subparts: a sequence cut short is one, bytes that never start one each
  // one, a surrogate (ED A0 80: ED then two strays) three; valid text unchanged
  CHECK(with_replacement_characters("caf\xC3\xA9 \xE6\x97\xA5") == "caf\xC3\xA9 \xE6\x97\xA5");
  CHECK(with_replacement_characters("a\xE2\x82z") == "a" + fffd + "z");
  CHECK(with_replacement_characters("\xF0\x9F\x98") == fffd);
  CHECK(with_replacement_characters("\xC0\xAF") == fffd + fffd);
  CHECK(with_replacement_characters("\xED\xA0\x80") == fffd + fffd + fffd);
  CHECK(with_replacement_characters("\xF4\x90\x80\x80") == fffd + fffd + fffd + fffd);
  CHECK(with_replacement_characters("\xFF\xFE") == fffd + fffd);
  CHECK(with_replacement_characters("\xE2\x82\xAC\xE2\x82") == "\xE2\x82\xAC" + fffd);
  CHECK(first_invalid_utf8(with_replacement_characters("\x80\xBF\xC2\xF5x\xE0\x80")) == std::string_view::npos);

  // In the picture: the same pixels as the text with U+FFFD written out, and visible
  const int w = 256, h = 64;
  const auto drawn = [&](const std::string& text) {
    AnnotationDesc d;
    d.font_path = kFont;
    d.texts = {{text, Corner::TopLeft}};
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 4, 0);
    draw_annotations(w, h, px.data(), d);
    return px;
  };
  const std::vector<std::uint8_t> blank(static_cast<std::size_t>(w) * h * 4, 0);
  CHECK(drawn("a\xE2\x82z") == drawn("a" + fffd + "z"));
  CHECK(drawn("a\xE2\x82z") != drawn("a" + fffd + fffd + "z"));
  CHECK(drawn("\xC0\xAF") == drawn(fffd + fffd));
  CHECK(drawn("\xFF") == drawn(fffd));
  CHECK(drawn("\xFF") != drawn(" "));  // a glyph, not a blank
  CHECK(drawn(fffd) != blank);
}

TEST_CASE("annotation values out of range and unreadable fonts are errors", "[annotate]") {
  AnnotationDesc d = desc_with(Corner::TopLeft, BarOrientation::Vertical);
  std::vector<std::uint8_t> px = pattern(64, 64);
  d.font_path = "/nonexistent/font.ttf";
  CHECK_THROWS_WITH(draw_annotations(64, 64, px.data(), d), Contains("cannot load font '/nonexistent/font.ttf'"));
  tessera_test::TempDir dir;
  d.font_path = dir.write("not_a_font.ttf", "plain text, not a font");
  CHECK_THROWS_WITH(validate_annotations(d), Contains("not_a_font.ttf"));
  d = desc_with(Corner::TopLeft, BarOrientation::Vertical);
  d.bar.length = 1.5;
  CHECK_THROWS_WITH(validate_annotations(d), Contains("colorbar length 1.5 is out of range"));
  d.bar.length = 0.4;
  d.font_size = 0.0;
  CHECK_THROWS_WITH(validate_annotations(d), Contains("font_size 0 is out of range"));
  // A bar as long as the image leaves no room for its labels
  d = desc_with(Corner::TopLeft, BarOrientation::Vertical);
  d.bar.length = 1.0;
  std::string why;
  CHECK_FALSE(annotations_fit(256, 256, layout_annotations(256, 256, d), &why));
  CHECK_THAT(why, Contains("the colour bar with its labels needs"));
}

TEST_CASE("write_png draws annotations into the PNG only, and without them the bytes are as before",
          "[annotate][image_io]") {
  tessera_test::TempDir dir;
  Image img;
  img.width = 200;
  img.height = 150;
  img.rgba.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  for (std::size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = static_cast<float>((i * 37 % 101) / 60.0);
  const ToneMap tm{};
  const AnnotationDesc d = desc_with(Corner::TopRight, BarOrientation::Horizontal);

  // PNG: without annotations, exactly the tone-mapped pixels; with them, changes only inside
  const ImageFormatInfo& png = image_format(ImageFormat::Png);
  png.write(dir.file("bare.png"), img, tm, nullptr);
  png.write(dir.file("noted.png"), img, tm, &d);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> bare = read_png_rgba(dir.file("bare.png"), w, h);
  const std::vector<std::uint8_t> noted = read_png_rgba(dir.file("noted.png"), w, h);
  CHECK(bare == png_pixels(img, tm));
  const AnnotationLayout l = layout_annotations(w, h, d);
  long inside_changed = 0, outside_changed = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool inside = false;
      for (const PixelBox& b : l.boxes) inside = inside || b.contains(x, y);
      (inside ? inside_changed : outside_changed) += !same_pixel(bare, noted, w, x, y);
    }
  CHECK(inside_changed > 0);
  CHECK(outside_changed == 0);

  // EXR: the same bytes with annotations as without
  const ImageFormatInfo& exr = image_format(ImageFormat::Exr);
  exr.write(dir.file("bare.exr"), img, tm, nullptr);
  exr.write(dir.file("noted.exr"), img, tm, &d);
  CHECK(bytes_of(dir.file("bare.exr")) == bytes_of(dir.file("noted.exr")));

  // A font that cannot be loaded: an error naming the file, and no PNG
  AnnotationDesc bad = d;
  bad.font_path = dir.file("missing.ttf");
  CHECK_THROWS_WITH(png.write(dir.file("x.png"), img, tm, &bad), Contains("missing.ttf"));
  CHECK_FALSE(std::filesystem::exists(dir.file("x.png")));
}
