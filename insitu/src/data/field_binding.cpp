#include "data/field_binding.h"

#include <tessera/byte_span.h>
#include <tessera/cuda_render.h>
#include <tessera/host_readable.h>
#include <tessera/loop_bounds.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

namespace tessera::insitu {
namespace {

constexpr const char* kAxis = "ijk";

// bind_field turns a tessera_dtype into a DType by its value: the two enums must list the
// dtypes in the same order, from the same first value.
static_assert(static_cast<int>(DType::UInt8) == TESSERA_UINT8, "tessera_dtype and DType differ");
static_assert(static_cast<int>(DType::Int16) == TESSERA_INT16, "tessera_dtype and DType differ");
static_assert(static_cast<int>(DType::UInt16) == TESSERA_UINT16, "tessera_dtype and DType differ");
static_assert(static_cast<int>(DType::Float32) == TESSERA_FLOAT32, "tessera_dtype and DType differ");
static_assert(static_cast<int>(DType::Float64) == TESSERA_FLOAT64, "tessera_dtype and DType differ");

std::string triple(const std::int64_t v[3]) {
  return std::to_string(v[0]) + "x" + std::to_string(v[1]) + "x" + std::to_string(v[2]);
}

[[noreturn]] void fail(const std::string& label, const std::string& fault) {
  throw std::invalid_argument(label + ": " + fault);
}

/// The array's bytes, from its lowest to one past its highest byte, must not wrap around the
/// address space (nor leave the int64 range that the renderer's index arithmetic uses).
void check_extent(const std::string& label, const tessera_field& f, std::size_t elem) {
  __int128 lo = 0, hi = static_cast<__int128>(elem);
  for (int a = 0; a < 3; ++a) {
    const __int128 span = static_cast<__int128>(f.dims[a] - 1) * f.byte_strides[a];
    (span < 0 ? lo : hi) += span;
  }
  const __int128 base = static_cast<__int128>(reinterpret_cast<std::uintptr_t>(f.data));
  const __int128 kI64 = static_cast<__int128>(INT64_MAX);
  if (hi - lo > kI64 || base + lo < 0 || base + hi > static_cast<__int128>(UINTPTR_MAX))
    fail(label, "byte strides reach outside the address space (array of " + triple(f.dims) + " with strides " +
                    std::to_string(f.byte_strides[0]) + ", " + std::to_string(f.byte_strides[1]) + ", " +
                    std::to_string(f.byte_strides[2]) + " from " +
                    std::to_string(static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(f.data))) + ")");
}

void check_grid(const std::string& label, const tessera_grid& g, const std::int64_t real[3]) {
  for (int a = 0; a < 3; ++a) {
    const std::string ax = std::string("[") + std::to_string(a) + "] (" + kAxis[a] + ")";
    if (!std::isfinite(g.origin[a])) fail(label, "grid origin" + ax + " is not finite");
    if (!std::isfinite(g.spacing[a]) || !(g.spacing[a] > 0.0))
      fail(label, "grid spacing" + ax + " = " + short_number(g.spacing[a]) + ", must be finite and > 0");
    if (g.spacing[a] < kMinSpacing || g.spacing[a] > kMaxSpacing)
      fail(label, "grid spacing" + ax + " = " + short_number(g.spacing[a]) + " is outside [1e-100, 1e100]");
    if (g.global_dims[a] < 1)
      fail(label, "grid global_dims" + ax + " = " + std::to_string(g.global_dims[a]) + ", must be >= 1");
    if (g.offset[a] < 0) fail(label, "grid offset" + ax + " = " + std::to_string(g.offset[a]) + ", must be >= 0");
    if (real[a] > g.global_dims[a] - g.offset[a])
      fail(label, "does not fit the grid along " + std::string(1, kAxis[a]) + ": " + std::to_string(real[a]) +
                      " real vertices at offset " + std::to_string(g.offset[a]) + " reach past global_dims " +
                      std::to_string(g.global_dims[a]) + " (real dims " + triple(real) + ", global dims " +
                      triple(g.global_dims) + ")");
  }
  // The data's corners within 2^40 smallest spacings of 0 (loop_bounds.h), as the CLI's
  // volume.origin: past that a double no longer resolves a voxel, and every camera or light
  // placed about the data would be blamed for the grid's fault
  const double h = std::min({g.spacing[0], g.spacing[1], g.spacing[2]});
  const double lim = kMaxCoordinateVoxels * h;
  for (int a = 0; a < 3; ++a) {
    const double far = g.origin[a] + static_cast<double>(g.global_dims[a] - 1) * g.spacing[a];
    if (!(std::fabs(g.origin[a]) <= lim && std::fabs(far) <= lim))
      fail(label, "grid origin [" + short_number(g.origin[0]) + ", " + short_number(g.origin[1]) + ", " +
                      short_number(g.origin[2]) + "] with spacing [" + short_number(g.spacing[0]) + ", " +
                      short_number(g.spacing[1]) + ", " + short_number(g.spacing[2]) +
                      "] puts the data (far corner along " + kAxis[a] + " at " + short_number(far) +
                      ") beyond 2^40 smallest spacings (" + short_number(lim) +
                      ") from 0, where a double no longer resolves a voxel");
  }
}

}  // namespace

std::string field_label(const tessera_field& f) { return std::string("field '") + (f.name ? f.name : "(null)") + "'"; }

bool FieldBinding::whole() const {
  if (blocks.size() != 1 || nlevels > 1) return false;
  for (int a = 0; a < 3; ++a)
    if (blocks[0].offset[a] != 0 || blocks[0].view.dims[a] != placement.global_dims[a]) return false;
  return true;
}

int find_field(std::span<const tessera_field> fields, const std::string& field_name, const std::string& render_name) {
  // Names non-null and distinct: sorted once, O(n log n) (a quadratic scan cost seconds at
  // thousands of fields); the pair reported is the first duplicate in name order
  std::vector<std::pair<std::string_view, std::size_t>> names_sorted;
  names_sorted.reserve(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!fields[i].name) throw std::invalid_argument("fields[" + std::to_string(i) + "]: name is null");
    names_sorted.emplace_back(fields[i].name, i);
  }
  std::sort(names_sorted.begin(), names_sorted.end());
  for (std::size_t q = 1; q < names_sorted.size(); ++q)
    if (names_sorted[q].first == names_sorted[q - 1].first)
      throw std::invalid_argument(field_label(fields[names_sorted[q].second]) + ": published twice (fields[" +
                                  std::to_string(names_sorted[q - 1].second) + "] and fields[" +
                                  std::to_string(names_sorted[q].second) + "])");
  if (field_name.empty()) {
    if (fields.size() == 1) return 0;
    throw std::invalid_argument("render '" + render_name + "' names no field and " + std::to_string(fields.size()) +
                                " fields are published (give `field:` in the config)");
  }
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (field_name == fields[i].name) return static_cast<int>(i);
  std::string names;
  for (const auto& f : fields) names += (names.empty() ? "" : ", ") + std::string(f.name);
  throw std::invalid_argument("field '" + field_name + "' (render '" + render_name +
                              "') is unknown: published fields are " + (names.empty() ? std::string("none") : names));
}

FieldView bind_array(const tessera_field& f, const std::string& label, bool cells) {
  // Descriptor of the whole array, ghosts included
  const int dt = raw_int(f.dtype);
  if (dt < TESSERA_UINT8 || dt > TESSERA_FLOAT64)
    fail(label, "dtype " + std::to_string(dt) + " is out of range (TESSERA_UINT8 .. TESSERA_FLOAT64)");
  const DType dtype = static_cast<DType>(dt);
  // Extents before the pointer: an empty array (Fortran's zero-size section, whose address
  // is NULL) is reported as empty along its axis, not as a missing pointer
  for (int a = 0; a < 3; ++a) {
    if (f.dims[a] == 0)
      fail(label, "zero-size array: dims[" + std::to_string(a) + "] (" + kAxis[a] + ") = 0, " +
                      "each extent must be >= 1 (dims " + triple(f.dims) + ")");
    if (f.dims[a] < 0)
      fail(label,
           "dims[" + std::to_string(a) + "] (" + kAxis[a] + ") = " + std::to_string(f.dims[a]) + ", must be >= 1");
  }
  if (!f.data) fail(label, "data pointer is null (dims " + triple(f.dims) + ")");
  for (int a = 0; a < 3; ++a) {
    if (f.ghosts_lo[a] < 0 || f.ghosts_hi[a] < 0) fail(label, "negative ghost width along " + std::string(1, kAxis[a]));
    if (f.ghosts_lo[a] >= f.dims[a] || f.ghosts_hi[a] >= f.dims[a] - f.ghosts_lo[a])
      fail(label, "ghost layers along " + std::string(1, kAxis[a]) + " (" + std::to_string(f.ghosts_lo[a]) + " + " +
                      std::to_string(f.ghosts_hi[a]) + ") leave no real " + (cells ? "cell" : "vertex") + " of dims " +
                      std::to_string(f.dims[a]));
  }
  FieldView full;
  full.data = f.data;
  full.dtype = dtype;
  for (int a = 0; a < 3; ++a) {
    full.dims[a] = f.dims[a];
    full.byte_strides[a] = f.byte_strides[a];
  }
  check_extent(label, f, dtype_size(dtype));  // first: validate() assumes no overflow
  full.validate(label);                       // zero or overlapping strides
  return FieldView::with_ghosts(f.data, dtype, f.dims, f.byte_strides, f.ghosts_lo, f.ghosts_hi);
}

FieldBinding bind_field(const tessera_field& f, const tessera_grid& g) {
  const std::string label = field_label(f);
  FieldBinding b;
  b.local = bind_array(f, label);
  // Real region and its place in the grid
  check_grid(label, g, b.local.dims);
  for (int a = 0; a < 3; ++a) {
    b.placement.global_dims[a] = g.global_dims[a];
    b.placement.offset[a] = g.offset[a];
  }
  b.geometry.origin = Vec3(g.origin[0], g.origin[1], g.origin[2]);
  b.geometry.spacing = Vec3(g.spacing[0], g.spacing[1], g.spacing[2]);
  const Vec3 n(static_cast<double>(g.global_dims[0] - 1), static_cast<double>(g.global_dims[1] - 1),
               static_cast<double>(g.global_dims[2] - 1));
  b.global_bounds = Bounds{b.geometry.origin, b.geometry.origin + n * b.geometry.spacing};
  FieldBlock block;
  block.view = b.local;
  for (int a = 0; a < 3; ++a) block.offset[a] = g.offset[a];
  b.blocks.push_back(block);
  return b;
}

void require_readable(const FieldBinding& b, const std::string& label) {
  for (std::size_t i = 0; i < b.blocks.size(); ++i) {
    const FieldView& v = b.blocks[i].view;
    if (cuda_memory_kind(v.data) != MemoryKind::Host) continue;  // managed pages would migrate
    const ByteSpan sp = byte_span(v);
    const auto* lo = static_cast<const unsigned char*>(v.data) + sp.lo;
    const auto bad = unreadable_byte(lo, static_cast<std::size_t>(sp.bytes()));
    if (!bad) continue;
    char where[32];
    std::snprintf(where, sizeof where, "%p", v.data);
    fail(label + (b.blocks.size() > 1 ? ", block " + std::to_string(i) : std::string()),
         std::string("data pointer ") + where + " is not readable host memory: byte " + std::to_string(*bad) +
             " of the " + std::to_string(sp.bytes()) +
             " bytes the render reads cannot be read (freed or unmapped memory, an array smaller than its dims and "
             "strides say, or device memory the CUDA runtime does not know, such as a freed cudaMalloc pointer)");
  }
}

void require_whole_grid(const tessera_field& field, const FieldBinding& b) {
  for (int a = 0; a < 3; ++a)
    if (b.placement.offset[a] != 0 || b.local.dims[a] != b.placement.global_dims[a])
      fail(field_label(field),
           "a single rank must hold the whole grid, but its real vertices " + triple(b.local.dims) + " at offset (" +
               std::to_string(b.placement.offset[0]) + ", " + std::to_string(b.placement.offset[1]) + ", " +
               std::to_string(b.placement.offset[2]) + ") do not cover global_dims " + triple(b.placement.global_dims));
}

}  // namespace tessera::insitu
