// `transfer_function:`: range, density scale and the piecewise-linear TFs of u.
#include <tessera/config/colormaps.h>
#include <tessera/config/render_defaults.h>
#include <tessera/config/transfer_function_spec.h>
#include <tessera/transfer_function.h>

#include "parsers.h"

#include <cctype>
#include <string>
#include <string_view>

namespace tessera::config::detail {
namespace {

const Range kU = Range::closed(0.0, 1.0);

/// Throws unless u >= the previous point's u.
void check_order(const Value& u_value, double u, const auto& points) {
  if (!points.empty() && u < points.back().u) {
    u_value.fail(format_number(u) + " is less than the previous u " + format_number(points.back().u) +
                 " (allowed: u in [0, 1], non-decreasing)");
  }
}

std::vector<ScalarPoint> parse_scalar_points(const Value& v, const Range& values) {
  const std::string allowed = "[[u, value], ...], u in [0, 1] non-decreasing, value in " + values.describe();
  std::vector<ScalarPoint> out;
  for (const Value& p : v.list(allowed, 1, kMaxTfPoints)) {
    const auto uv = p.list("[u, value]", 2, 2);
    const double u = uv[0].number(kU);
    check_order(uv[0], u, out);
    out.push_back({u, uv[1].number(values)});
  }
  return out;
}

ColorTFSpec parse_color_points(const Value& v, const Range& components) {
  const std::string cmaps = join_words(colormap_names());
  if (v.is_scalar()) {
    const std::string name = v.string();
    if (!find_colormap(name)) {
      v.fail(v.describe() + " is not a colormap (allowed: " + cmaps +
             " (add _r to reverse), or [[u, [r, g, b]], ...])");
    }
    return ColorTFSpec{name, {}};
  }
  const std::string allowed = "[[u, [r, g, b]], ...] with u in [0, 1] non-decreasing and "
                              "components in " +
                              components.describe() + ", or a colormap: " + cmaps;
  ColorTFSpec s;
  for (const Value& p : v.list(allowed, 1, kMaxTfPoints)) {
    const auto uc = p.list("[u, [r, g, b]]", 2, 2);
    const double u = uc[0].number(kU);
    check_order(uc[0], u, s.points);
    s.points.push_back({u, uc[1].color(components)});
  }
  return s;
}

RangeSpec parse_range(const Value& v) {
  if (v.is_word("auto")) return RangeSpec{true, 0.0, 1.0};
  if (v.is_scalar()) v.fail(v.describe() + " is not a range (allowed: [lo, hi] with lo < hi, or auto)");
  const auto lh = v.list("[lo, hi] with lo < hi, or auto", 2, 2);
  const double lo = lh[0].number(), hi = lh[1].number();
  if (!(lo < hi)) {
    v.fail("lo " + format_number(lo) + " is not below hi " + format_number(hi) +
           " (allowed: [lo, hi] with lo < hi, or auto)");
  }
  return RangeSpec{false, lo, hi};
}

// `density_scale: {optical_depth: t}`: extinction relative to the data's diagonal
constexpr KeyShape kDensityKeys[] = {{"optical_depth", "t"}};

/// `density_scale`: a number >= 0 (per world unit), `auto` or `{optical_depth: t}`.
void parse_density_scale(const Value& v, TransferFunctionSpec& tf) {
  const std::string allowed = "a number >= 0, the extinction per world unit at opacity 1; auto; or " +
                              braced(kDensityKeys) + ", t >= 0 the optical depth of the data's diagonal at opacity 1";
  if (v.is_word("auto")) {
    tf.density_scale = kDefaultOpticalDepth;
    tf.density_relative = true;
    return;
  }
  if (v.is_scalar()) {
    // A word (`atuo`) is told what is allowed; a number, or what tries to be one, gets number()'s range check
    const std::string_view t = v.text();
    if (!t.empty() && std::isalpha(static_cast<unsigned char>(t.front())))
      v.fail(v.describe() + " is not a density scale (allowed: " + allowed + ")");
    tf.density_scale = v.number(Range::at_least(0.0));
    tf.density_relative = false;
    return;
  }
  const Map m = v.map(allowed);
  m.allow(kDensityKeys);
  tf.density_scale = m.require("optical_depth", "t >= 0, the optical depth of the data's diagonal at opacity 1")
                         .number(Range::at_least(0.0));
  tf.density_relative = true;
}

}  // namespace

TransferFunctionSpec parse_transfer_function(const Value& v) {
  const Map m = v.map_with_keys({"range", "density_scale", "opacity", "diffuse", "specular", "roughness", "emission"});
  TransferFunctionSpec tf;
  tf.range.automatic = true;
  if (const auto r = m.get("range")) tf.range = parse_range(*r);
  if (const auto d = m.get("density_scale")) parse_density_scale(*d, tf);
  const auto opacity = m.get("opacity");
  tf.opacity = opacity ? parse_scalar_points(*opacity, Range::at_least(0.0)) : default_opacity();
  if (const auto d = m.get("diffuse")) tf.diffuse = parse_color_points(*d, kU);
  if (const auto s = m.get("specular")) tf.specular = parse_color_points(*s, kU);
  if (const auto r = m.get("roughness")) tf.roughness = parse_scalar_points(*r, kU);
  if (const auto e = m.get("emission")) tf.emission = parse_color_points(*e, Range::at_least(0.0));
  return tf;
}

}  // namespace tessera::config::detail
