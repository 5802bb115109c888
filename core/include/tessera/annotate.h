#pragma once
/// Annotations drawn into the 8-bit picture (the PNG) after tone mapping: a colour bar of the
/// transfer function and lines of text, rendered with FreeType from a TrueType/OpenType font
/// (anti-aliased, kerned where the font has kerning), each item on a translucent dark backing
/// with a dark outline around white glyphs, so it reads on any background. The float image
/// (the EXR) is never touched.
///
/// Layout: every item sits in one of the four corners, inset by a margin; items sharing a
/// corner stack in the order given (texts, then the colour bar), first item nearest the top.
/// Sizes scale with the image: the font is font_size * min(width, height) pixels, at least
/// kMinFontPixels and at most kMaxFontPixels. Drawing is clipped to the image and bounded in time whatever the text:
/// each text is cut at kMaxAnnotationGlyphs glyphs and at the image width.
///
/// Thread-safety: every function is safe to call concurrently (each call opens its own
/// FreeType instance).
#include <tessera/transfer_function.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera {

enum class Corner { TopLeft, TopRight, BottomLeft, BottomRight };
enum class BarOrientation { Vertical, Horizontal };

/// Smallest font, in pixels, whatever the image size (legible at 256 px images).
inline constexpr int kMinFontPixels = 11;
/// Largest font, in pixels (a font_size on a huge image): bounds the drawing's cost.
inline constexpr int kMaxFontPixels = 1024;
/// Glyphs drawn per text at most; the rest of a longer text is not drawn.
inline constexpr std::size_t kMaxAnnotationGlyphs = 256;
/// Texts per picture at most (more are refused by validate_annotations).
inline constexpr std::size_t kMaxAnnotationTexts = 8;

/// The colour bar of `AnnotationDesc::tf`: along its length the diffuse colour from the TF's
/// first value (lo; bottom or left) to its last (hi; top or right). Across its thickness two
/// bands: the colour itself (the outer half: left of a vertical bar, top of a horizontal
/// one) and the colour with alpha = opacity / (the opacity's maximum) over a grey checker.
/// Tick labels in data units at "nice" values (1, 2 or 5 x 10^k) right of (vertical) or
/// below (horizontal) the bar, fewer than `ticks` where neighbouring labels would touch,
/// written by colorbar_labels (distinct, and true to their ticks at any range);
/// `label` (the field name) above it.
struct ColorBarDesc {
  Corner corner = Corner::BottomRight;
  BarOrientation orientation = BarOrientation::Vertical;
  double length = 0.4;      ///< fraction of the image edge the bar runs along, (0, 1]
  double thickness = 0.04;  ///< fraction of the image's smaller edge, (0, 1]
  int ticks = 5;            ///< about this many tick labels, [2, 10]
  std::string label;        ///< drawn above the bar; empty = none
};

struct AnnotationText {
  std::string text;  ///< UTF-8; invalid bytes show as U+FFFD; empty = nothing drawn
  Corner corner = Corner::TopLeft;
};

struct AnnotationDesc {
  std::string font_path;    ///< a TrueType/OpenType file FreeType opens
  double font_size = 0.03;  ///< fraction of min(width, height), (0, 1]; kMinFontPixels .. kMaxFontPixels
  std::vector<AnnotationText> texts;
  bool colorbar = false;
  ColorBarDesc bar;
  TransferFunction tf;  ///< the colour bar's: range lo..hi, diffuse colours, opacity
};

/// A pixel rectangle [x0, x1) x [y0, y1), row 0 at the top.
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

/// Where draw_annotations draws, for a width x height picture. Boxes are not clipped: one
/// reaching outside the image does not fit (annotations_fit).
struct AnnotationLayout {
  int font_pixels = 0;
  std::vector<PixelBox> boxes;        ///< one per drawn item (texts, then the bar): everything drawn lies inside
  PixelBox bar;                       ///< the bar itself (both bands), empty without a colour bar
  PixelBox color_band;                ///< the plain-colour band of the bar
  PixelBox opacity_band;              ///< the opacity band of the bar
  std::vector<PixelBox> tick_labels;  ///< each tick label's text, first value first
};

/// Throws std::invalid_argument naming the fault for values out of range (font_size,
/// length, thickness, ticks, too many texts, a TF with lo >= hi); std::runtime_error naming
/// the file when FreeType cannot open font_path.
void validate_annotations(const AnnotationDesc& desc);

/// The layout for a width x height picture (opens the font to measure the texts). Throws like
/// validate_annotations.
AnnotationLayout layout_annotations(int width, int height, const AnnotationDesc& desc);

/// Whether every box of the layout lies inside the image; if not, `why` says which item needs
/// how many pixels.
bool annotations_fit(int width, int height, const AnnotationLayout& layout, std::string* why = nullptr);

/// Draws into `rgba8` (width*height*4 bytes, straight alpha, row 0 at the top, sRGB) inside
/// the layout's boxes only, clipped to the image. Throws like validate_annotations.
void draw_annotations(int width, int height, std::uint8_t* rgba8, const AnnotationDesc& desc);

/// The tick values of a colour bar over [lo, hi]: multiples of a step of 1, 2 or 5 x 10^k
/// chosen to give about `target` ticks, all inside [lo, hi], distinct and ascending; {lo, hi}
/// when no such step exists (a range too narrow for its magnitude). At most 2 * target + 2
/// values. Safe for every finite lo < hi, a width that overflows (-1e308 to 1e308) included.
std::vector<double> colorbar_ticks(double lo, double hi, int target);

/// The labels of `ticks` (distinct and ascending, as colorbar_ticks gives them, or lo alone)
/// on a colour bar over [lo, hi], one per tick. Each is its tick rounded once, exactly, at
/// the decimal place of the step between ticks (of hi - lo for a single tick), finer only
/// where neighbours would read alike: consecutive labels always differ, and each reads as its
/// tick to within half a unit in its last digit. Fixed point for magnitudes 0.001 to 99999 and
/// wherever shorter ("0.25", "320", "101324.6"), else scientific ("1.5e+06"); where these would
/// be longer than 12 characters (a narrow range far from zero) a round base and exact offsets,
/// "1e+16 + 2", "-101325 - 0.0004", the base alone at the tick equal to it. A single label is
/// at most 12 characters (rounded coarser where needed, still true to its digits). Never "-0".
std::vector<std::string> colorbar_labels(const std::vector<double>& ticks, double lo, double hi);

/// One value as text, rounded at the decimal place of `step` as colorbar_labels rounds it, in
/// the notation the largest magnitude `largest_magnitude` takes there: "0.25", "150",
/// "1.5e+06"; never "-0". No offsets and no check against neighbours: colorbar_labels does both.
std::string tick_label(double v, double step, double largest_magnitude);

}  // namespace tessera
