/// MagnitudeField (magnitude_field.h): validation and the summary of the magnitudes.
#include <tessera/magnitude_field.h>

#include <tessera/brick_cache.h>

#include "field/summary_accumulate.h"

#include <stdexcept>

namespace tessera {
namespace {

/// Element (i, j, k) of component c's typed view as double.
double load(const FieldView& f, std::int64_t i, std::int64_t j, std::int64_t k) {
  const auto* p =
      static_cast<const unsigned char*>(f.data) + i * f.byte_strides[0] + j * f.byte_strides[1] + k * f.byte_strides[2];
  return detail::load_as_double(f.dtype, p);
}

}  // namespace

void MagnitudeField::validate(const std::string& what) const {
  static const char* names[3] = {"component 0", "component 1", "component 2"};
  for (int c = 0; c < 3; ++c) components[c].validate(what + " " + names[c]);
  for (int c = 1; c < 3; ++c)
    for (int a = 0; a < 3; ++a)
      if (components[c].dims[a] != components[0].dims[a])
        throw std::invalid_argument(
            what + ": " + names[c] + " has " + std::to_string(components[c].dims[0]) + "x" +
            std::to_string(components[c].dims[1]) + "x" + std::to_string(components[c].dims[2]) +
            " elements, component 0 " + std::to_string(components[0].dims[0]) + "x" +
            std::to_string(components[0].dims[1]) + "x" + std::to_string(components[0].dims[2]));
}

void accumulate_magnitude(FieldSummary::Parts& parts, const MagnitudeField& block, const std::int64_t offset[3],
                          const std::int64_t global_dims[3], int edge) {
  summary_detail::check_parts(parts, global_dims, edge);
  block.validate("block");
  summary_detail::check_block_inside(block.dims(), offset, global_dims);
  const FieldView* c = block.components;
  summary_detail::accumulate_values(parts, block.dims(), offset, edge,
                                    [&](std::int64_t i, std::int64_t j, std::int64_t k) {
                                      return magnitude(load(c[0], i, j, k), load(c[1], i, j, k), load(c[2], i, j, k));
                                    });
}

std::shared_ptr<const FieldSummary> magnitude_summary(const MagnitudeField& field, int edge) {
  field.validate();
  const std::int64_t offset[3] = {0, 0, 0};
  FieldSummary::Parts parts;
  if (edge < 1) throw std::invalid_argument("macrocell edge must be >= 1, got " + std::to_string(edge));
  for (int a = 0; a < 3; ++a) parts.cells[a] = summary_detail::cells_along(field.dims()[a], edge);
  const auto n = static_cast<std::size_t>(parts.cells[0] * parts.cells[1] * parts.cells[2]);
  parts.lo.assign(n, summary_detail::kInf);
  parts.hi.assign(n, -summary_detail::kInf);
  parts.flags.assign(n, 0);
  accumulate_magnitude(parts, field, offset, field.dims(), edge);
  FieldLayout layout = FieldLayout::of(field.components[0]);
  layout.dtype = DType::Float64;
  return FieldSummary::from_parts(std::move(parts), layout, edge);
}

}  // namespace tessera
