#pragma once
/// AxisTables: what prepare() derives from a field's rectilinear axes (VolumeGeometry::coords):
/// per such axis a uniform bin table for the world -> segment lookup and the world position of
/// each macrocell wall (kernel/axis_map.h reads both). The caller's coordinates are never
/// copied. Also the per-axis checks and figures the rest of prepare needs (finite and strictly
/// increasing coordinates, smallest spacing, bounds), for uniform and rectilinear axes alike.
#include <tessera/field_view.h>
#include <tessera/scene.h>

#include "kernel/axis_map.h"

#include <cstdint>
#include <vector>

namespace tessera {

/// "x", "y" or "z".
const char* axis_name(int a);

/// Knots (samples) along axis a: field.dims[a] vertices or cell centres.
inline std::int64_t axis_knots(const FieldView& field, int a) { return field.dims[a]; }

/// Coordinates the caller passes for a rectilinear axis: dims[a] (vertex data) or dims[a] + 1
/// (cell data).
std::int64_t axis_coordinate_count(const FieldView& field, const VolumeGeometry& g, int a);

/// Throws std::invalid_argument naming the axis and index unless every rectilinear axis'
/// coordinates are finite and strictly increasing. Reads dims[a] (+ 1) values per such axis.
void validate_axes(const FieldView& field, const VolumeGeometry& g);

/// Smallest / largest distance between neighbouring coordinates along axis a (world units):
/// spacing[a] on a uniform axis; on a rectilinear one the smallest / largest vertex interval
/// or cell width; Inf / 0 for a rectilinear vertex axis of one vertex. Coordinates validated.
double smallest_spacing(const FieldView& field, const VolumeGeometry& g, int a);
double largest_spacing(const FieldView& field, const VolumeGeometry& g, int a);
/// The smallest over the three axes (1 when no axis has an interval).
double smallest_spacing(const FieldView& field, const VolumeGeometry& g);

/// Entries of the bin table of a rectilinear axis with n knots over [lo, hi] whose smallest
/// knot interval is h: enough bins that each holds at most one knot, but at most 4 (n - 1) + 64.
std::int64_t axis_bin_count(std::int64_t n, double lo, double hi, double h);

/// Bytes AxisTables::build allocates for this field and geometry with macrocell edge `edge`.
std::uint64_t axis_table_bytes(const FieldView& field, const VolumeGeometry& g, int edge);

/// Not copyable: the maps point into the tables.
class AxisTables {
 public:
  AxisTables() = default;
  AxisTables(const AxisTables&) = delete;
  AxisTables& operator=(const AxisTables&) = delete;
  /// Tables of every rectilinear axis of a validated field and geometry; nc: the majorant
  /// grid's macrocells per axis, edge its edge in knots.
  void build(const FieldView& field, const VolumeGeometry& g, int edge, const std::int64_t nc[3]);
  /// The kernels' map of axis a (coords == nullptr: uniform). Points into this object.
  const AxisMap& map(int a) const { return m_map[a]; }
  bool any_rectilinear() const { return m_map[0].coords || m_map[1].coords || m_map[2].coords; }
  std::uint64_t bytes() const;

 private:
  AxisMap m_map[3];
  std::vector<std::int64_t> m_bins[3];
  std::vector<double> m_walls[3];
};

}  // namespace tessera
