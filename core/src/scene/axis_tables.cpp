#include "scene/axis_tables.h"

#include <tessera/number_text.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

using u64 = std::uint64_t;

/// The knots' map of axis a without tables (coords, cell, n, lo, hi).
AxisMap bare_map(const FieldView& field, const VolumeGeometry& g, int a) {
  AxisMap m;
  m.coords = g.coords[a];
  m.cell = g.association == Association::Cell;
  m.n = axis_knots(field, a);
  if (m.coords) {
    m.lo = m.knot(0);
    m.hi = m.knot(m.n - 1);
  }
  return m;
}

/// Smallest interval between neighbouring knots of a rectilinear axis (Inf when n < 2).
double smallest_knot_interval(const AxisMap& m) {
  double h = INFINITY;
  for (std::int64_t i = 0; i + 1 < m.n; ++i) h = std::min(h, m.knot(i + 1) - m.knot(i));
  return h;
}

}  // namespace

const char* axis_name(int a) {
  static constexpr const char* kNames[] = {"x", "y", "z"};
  return kNames[a];
}

std::int64_t axis_coordinate_count(const FieldView& field, const VolumeGeometry& g, int a) {
  return field.dims[a] + (g.association == Association::Cell ? 1 : 0);
}

void validate_axes(const FieldView& field, const VolumeGeometry& g) {
  for (int a = 0; a < 3; ++a) {
    const double* c = g.coords[a];
    if (!c) continue;
    const std::int64_t count = axis_coordinate_count(field, g, a);
    const std::string what = std::string("rectilinear axis ") + axis_name(a) + " (" + std::to_string(count) +
                             (g.association == Association::Cell ? " cell boundaries" : " vertex coordinates") + ")";
    for (std::int64_t i = 0; i < count; ++i) {
      if (!std::isfinite(c[i]))
        throw std::invalid_argument(what + ": coordinate " + std::to_string(i) + " is " +
                                    (std::isnan(c[i]) ? std::string("NaN") : short_number(c[i])) +
                                    ", coordinates must be finite");
      if (i > 0 && !(c[i] > c[i - 1]))
        throw std::invalid_argument(what + ": coordinate " + std::to_string(i) + " (" + short_number(c[i]) +
                                    ") is not above coordinate " + std::to_string(i - 1) + " (" +
                                    short_number(c[i - 1]) + "), coordinates must be strictly increasing");
    }
  }
}

double smallest_spacing(const FieldView& field, const VolumeGeometry& g, int a) {
  const double* c = g.coords[a];
  if (!c) return g.spacing[a];
  double h = INFINITY;
  const std::int64_t count = axis_coordinate_count(field, g, a);
  for (std::int64_t i = 0; i + 1 < count; ++i) h = std::min(h, c[i + 1] - c[i]);
  return h;
}

double largest_spacing(const FieldView& field, const VolumeGeometry& g, int a) {
  const double* c = g.coords[a];
  if (!c) return g.spacing[a];
  double h = 0.0;
  const std::int64_t count = axis_coordinate_count(field, g, a);
  for (std::int64_t i = 0; i + 1 < count; ++i) h = std::max(h, c[i + 1] - c[i]);
  return h;
}

double smallest_spacing(const FieldView& field, const VolumeGeometry& g) {
  // Uniform geometry: exactly today's min over the spacing
  if (!g.coords[0] && !g.coords[1] && !g.coords[2]) return std::min({g.spacing.x, g.spacing.y, g.spacing.z});
  const double h =
      std::min({smallest_spacing(field, g, 0), smallest_spacing(field, g, 1), smallest_spacing(field, g, 2)});
  return std::isfinite(h) ? h : 1.0;
}

std::int64_t axis_bin_count(std::int64_t n, double lo, double hi, double h) {
  const std::int64_t cap = 4 * std::max<std::int64_t>(0, n - 1) + 64;
  if (n < 2 || !(hi > lo) || !(h > 0.0)) return 1;
  const double want = std::ceil((hi - lo) / h);
  return want < static_cast<double>(cap) ? std::max<std::int64_t>(1, static_cast<std::int64_t>(want)) : cap;
}

std::uint64_t axis_table_bytes(const FieldView& field, const VolumeGeometry& g, int edge) {
  u64 bytes = 0;
  for (int a = 0; a < 3; ++a) {
    if (!g.coords[a]) continue;
    const std::int64_t n = axis_knots(field, a);
    const u64 nc = static_cast<u64>(std::max<std::int64_t>(1, (n - 1 + edge - 1) / std::max(1, edge)));
    // The bin count is at most 4 (n - 1) + 64 whatever the coordinates: count the cap
    const u64 bins = static_cast<u64>(4 * std::max<std::int64_t>(0, n - 1) + 64) + 1;
    bytes += bins * sizeof(std::int64_t) + (nc + 1) * sizeof(double);
  }
  return bytes;
}

void AxisTables::build(const FieldView& field, const VolumeGeometry& g, int edge, const std::int64_t nc[3]) {
  for (int a = 0; a < 3; ++a) {
    m_map[a] = bare_map(field, g, a);
    m_bins[a].clear();
    m_walls[a].clear();
    AxisMap& m = m_map[a];
    if (!m.coords) continue;
    // Bin table: bins[b] = the last segment whose first knot is at or below bin b's start
    m.nbins = axis_bin_count(m.n, m.lo, m.hi, smallest_knot_interval(m));
    m.inv_bin = m.hi > m.lo ? static_cast<double>(m.nbins) / (m.hi - m.lo) : 0.0;
    std::vector<std::int64_t>& bins = m_bins[a];
    bins.resize(static_cast<std::size_t>(m.nbins) + 1);
    const std::int64_t last_seg = std::max<std::int64_t>(0, m.n - 2);
    std::int64_t s = 0;
    for (std::int64_t b = 0; b < m.nbins; ++b) {
      const double start = m.lo + static_cast<double>(b) / m.inv_bin;
      while (s < last_seg && m.knot(s + 1) <= start) ++s;
      bins[static_cast<std::size_t>(b)] = s;
    }
    bins[static_cast<std::size_t>(m.nbins)] = last_seg;
    if (m.n < 2) bins.assign(bins.size(), 0);
    m.bins = bins.data();
    // Macrocell walls: macrocell c spans knots [c edge, (c + 1) edge]
    std::vector<double>& walls = m_walls[a];
    walls.resize(static_cast<std::size_t>(nc[a]) + 1);
    for (std::int64_t c = 0; c <= nc[a]; ++c)
      walls[static_cast<std::size_t>(c)] = m.knot(std::min<std::int64_t>(c * edge, m.n - 1));
    m.walls = walls.data();
  }
}

std::uint64_t AxisTables::bytes() const {
  u64 b = 0;
  for (int a = 0; a < 3; ++a) b += m_bins[a].size() * sizeof(std::int64_t) + m_walls[a].size() * sizeof(double);
  return b;
}

}  // namespace tessera
