#pragma once
/// The `annotations:` block of a render, as written (validated at load time), and the core
/// description (tessera/annotate.h) one picture draws from it.
///
///   annotations:
///     colorbar: true            # or {corner, orientation, length, thickness, ticks, label}
///     text: "{name}  step {step}  t = {time:.3g}"
///     text_corner: top-left
///     title: "Heat"             # a pattern too; text and title in one corner stack, title first
///     title_corner: top-left
///     font: fonts/My.ttf        # default: kDefaultFontPath (then kFallbackFontPaths)
///     font_size: 0.03           # fraction of the image's smaller edge
///
/// `text` and `title` are patterns with the placeholders and format specs of output file
/// names (output_path.h) except {rank}: {name} (the render's name), {step}, {time}. In them and
/// in `label`, bytes that are not valid UTF-8 are replaced at load by U+FFFD, one per maximal
/// invalid subsequence, so the spec holds UTF-8 that is drawn and written back as it reads.
#include <tessera/annotate.h>
#include <tessera/transfer_function.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace tessera::config {

/// The font used when `font:` is not given: DejaVu Sans where Debian's fonts-dejavu-core puts it,
/// else the first of kFallbackFontPaths that exists (DejaVu Sans where Fedora, Arch and
/// openSUSE put it); none: a load-time error asking for `font:`.
inline constexpr const char* kDefaultFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
inline constexpr const char* kFallbackFontPaths[] = {"/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf",
                                                     "/usr/share/fonts/TTF/DejaVuSans.ttf",
                                                     "/usr/share/fonts/truetype/DejaVuSans.ttf"};
/// Longest `text` / `title` pattern and longest `label`, in bytes (with invalid UTF-8 made U+FFFD).
inline constexpr std::size_t kMaxAnnotationPattern = 256;

struct ColorBarSpec {
  Corner corner = Corner::BottomRight;
  BarOrientation orientation = BarOrientation::Vertical;
  double length = 0.4;               ///< (0, 1]: fraction of the edge the bar runs along
  double thickness = 0.04;           ///< (0, 1]: fraction of the smaller edge
  int ticks = 5;                     ///< [2, 10]
  std::optional<std::string> label;  ///< absent: the render's `field` (none if that is empty)
};

struct AnnotationsSpec {
  bool colorbar = false;
  ColorBarSpec bar;
  std::string text;  ///< pattern; "" = none
  Corner text_corner = Corner::TopLeft;
  std::string title;  ///< pattern; "" = none
  Corner title_corner = Corner::TopLeft;
  std::string font;         ///< absolute path of an existing font file FreeType opens (resolved at load)
  double font_size = 0.03;  ///< (0, 1]
};

/// Throws std::invalid_argument naming the fault: like validate_output_pattern without the
/// file-name rules, and {rank} is not a placeholder here.
void validate_text_pattern(const std::string& pattern);

/// The pattern expanded (throws like validate_text_pattern).
std::string format_text_pattern(const std::string& pattern, const std::string& name, std::int64_t step, double time);

/// The core description for one picture of render `name` (whose field is `field`) at `step`
/// and `time`, the colour bar showing `tf` (the render's TF with its range resolved).
AnnotationDesc build_annotations(const AnnotationsSpec& a, const std::string& name, const std::string& field,
                                 const TransferFunction& tf, std::int64_t step, double time);

}  // namespace tessera::config
