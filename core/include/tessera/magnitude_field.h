#pragma once
/// MagnitudeField: a scalar field that is the Euclidean norm of three component arrays that
/// someone else owns (a vector's u, v, w), evaluated per lookup, never copied.
///
/// Element (i, j, k) is magnitude(a, b, c), with a, b, c element (i, j, k) of each component
/// read as double. Each component is its own FieldView (its own data, dtype and byte strides:
/// three separate arrays, or three components of one interleaved array); all three have the
/// same dims. The result is a float64 field: the same value bit for bit whether it is read in
/// place by the kernels, packed into a replica, or summarised, since every path calls
/// magnitude() below.
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/host_device.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace tessera {

/// |(a, b, c)| as every path computes it: sqrt(a*a + b*b + c*c) in double, in that order.
/// NaN if a component is NaN; +Inf if one is infinite (and none is NaN), or if the sum
/// overflows (components near the double range).
TESSERA_HOST_DEVICE inline double magnitude(double a, double b, double c) { return std::sqrt(a * a + b * b + c * c); }

struct MagnitudeField {
  FieldView components[3];

  /// Throws std::invalid_argument naming `what`, the component and the fault: each component
  /// as FieldView::validate, and dims that differ between components.
  void validate(const std::string& what = "vector field") const;
  /// The dims of every component.
  const std::int64_t* dims() const { return components[0].dims; }
};

/// The summary of the magnitudes (field_summary.h) with macrocell edge `edge` (one pass over
/// the three components, TBB-parallel; bit-identical for any thread count and equal to the
/// summary of a float64 array holding the magnitudes). Its layout is component 0's with
/// dtype float64: never pass it as `reuse` to prepare(FieldView) (it could match component 0).
std::shared_ptr<const FieldSummary> magnitude_summary(const MagnitudeField& field, int edge);

/// The summary parts (FieldSummary::partial) of the magnitudes of one block at `offset` in a
/// field of `global_dims`, merged into `parts` (FieldSummary::accumulate's contract).
void accumulate_magnitude(FieldSummary::Parts& parts, const MagnitudeField& block, const std::int64_t offset[3],
                          const std::int64_t global_dims[3], int edge);

}  // namespace tessera
