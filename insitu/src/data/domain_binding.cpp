// Binding tessera_execute_domains' descriptors (domain_binding.h).
#include "data/domain_binding.h"

#include <tessera/amr.h>
#include <tessera/loop_bounds.h>
#include <tessera/number_text.h>

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

namespace tessera::insitu {
namespace {

constexpr const char* kAxis = "ijk";

std::string axis(int a) {
  std::string s = "[";
  s += std::to_string(a);
  s += "] (";
  s += kAxis[a];
  s += ')';
  return s;
}

[[noreturn]] void fail(const std::string& fault) { throw std::invalid_argument(fault); }

/// The association as the int the caller stored: a C caller may store any int in the enum,
/// and loading an out-of-range value as tessera_association is undefined (UBSan says so).
int association_value(const tessera_mesh& m) {
  int v;
  static_assert(sizeof v == sizeof m.association);
  std::memcpy(&v, &m.association, sizeof v);
  return v;
}

bool cell_data(const tessera_mesh& m) { return association_value(m) == TESSERA_CELL; }

/// Axis a's coordinates come in pieces from the domains (axes_from_domains).
bool pieced(const tessera_mesh& m, int a) { return ((m.axes_from_domains >> a) & 1) != 0; }

/// Coordinates along rectilinear axis a: global_dims (vertex) or global_dims + 1 (cell).
std::int64_t coord_count(const tessera_mesh& m, int a) { return m.global_dims[a] + (cell_data(m) ? 1 : 0); }

/// a + b in decimal, exact: an offset near INT64_MAX plus a length never wraps in a message.
std::string sum_text(std::int64_t a, std::int64_t b) {
  __int128 v = static_cast<__int128>(a) + b;
  const bool negative = v < 0;
  std::string digits;
  do {
    const int d = static_cast<int>(v % 10);
    digits.insert(digits.begin(), static_cast<char>('0' + (d < 0 ? -d : d)));
    v /= 10;
  } while (v != 0);
  return negative ? "-" + digits : digits;
}

std::string association_text(int assoc) {
  return assoc == TESSERA_CELL ? "cell data (TESSERA_CELL)" : "vertex data (TESSERA_VERTEX)";
}

/// What fields[f] of domain d is: the domain's associations[f], or the mesh's without them.
int field_association(const tessera_mesh& m, const tessera_domain& d, int f, const std::string& who) {
  if (!d.associations) return association_value(m);
  int v;
  static_assert(sizeof v == sizeof d.associations[f]);
  std::memcpy(&v, &d.associations[f], sizeof v);  // any int a C caller stored
  if (v != TESSERA_VERTEX && v != TESSERA_CELL)
    fail(who + ": associations[" + std::to_string(f) + "] = " + std::to_string(v) + " (field '" +
         std::string(d.fields[f].name ? d.fields[f].name : "(null)") +
         "') is neither TESSERA_VERTEX (0) nor TESSERA_CELL (1)");
  return v;
}

std::string dtype_text(tessera_dtype t) {
  const int d = static_cast<int>(t);
  return d >= TESSERA_UINT8 && d <= TESSERA_FLOAT64 ? dtype_name(static_cast<DType>(d)) : std::to_string(d);
}

}  // namespace

void check_mesh(const tessera_mesh& m) {
  const int assoc = association_value(m);
  if (assoc != TESSERA_VERTEX && assoc != TESSERA_CELL)
    fail("mesh: association " + std::to_string(assoc) + " is neither TESSERA_VERTEX (0) nor TESSERA_CELL (1)");
  if (m.nlevels < 1 || m.nlevels > kMaxAmrLevels)
    fail("mesh: nlevels = " + std::to_string(m.nlevels) + ", must be in [1, " + std::to_string(kMaxAmrLevels) +
         "] (1 = a single level; refinement levels 0 .. nlevels - 1)");
  // Refinement: nlevels - 1 ratios, each 2 or 4
  if (m.nlevels > 1 && !m.refinement)
    fail("mesh: refinement is NULL with nlevels = " + std::to_string(m.nlevels) + " (it must point to " +
         std::to_string(m.nlevels - 1) + " ratios, each 2 or 4)");
  std::int64_t finest = 1;  // R of the finest level: level-0 spacing / finest spacing
  for (int l = 0; l + 1 < m.nlevels; ++l) {
    if (m.refinement[l] != 2 && m.refinement[l] != 4)
      fail("mesh: refinement[" + std::to_string(l) + "] = " + std::to_string(m.refinement[l]) + " (level " +
           std::to_string(l) + " -> " + std::to_string(l + 1) + "), must be 2 or 4");
    finest *= m.refinement[l];
  }
  if (m.axes_from_domains & ~7)
    fail("mesh: axes_from_domains = " + std::to_string(m.axes_from_domains) +
         " has bits other than 1, 2 and 4 (axes i, j, k)");
  double lo[3], hi[3], h = INFINITY;
  bool known[3] = {true, true, true};  // the axis' extent (not for pieces still to assemble)
  std::string h_where;                 // where the smallest spacing is, for the message
  const auto smallest = [&](double s, int a, std::int64_t q) {
    if (!(s < h)) return;
    h = s;
    h_where = q < 0 ? "spacing" + axis(a)
                    : "coords" + axis(a) + "[" + std::to_string(q) + "] - [" + std::to_string(q - 1) + "]";
  };
  for (int a = 0; a < 3; ++a) {
    if (m.global_dims[a] < 1 || m.global_dims[a] > INT_MAX)
      fail("mesh: global_dims" + axis(a) + " = " + std::to_string(m.global_dims[a]) + ", must be in [1, " +
           std::to_string(INT_MAX) + "]");
    if (pieced(m, a)) {
      // Coordinates that the domains give in pieces (axis_pieces.h assembles them)
      if (m.coords[a])
        fail("mesh: axis " + std::string(1, kAxis[a]) + " has both coords" + axis(a) + " and bit " +
             std::to_string(1 << a) + " of axes_from_domains set: give the axis once");
      if (m.nlevels > 1)
        fail("mesh: axes_from_domains sets axis " + std::string(1, kAxis[a]) + " with nlevels = " +
             std::to_string(m.nlevels) + ": per-domain coordinates with refinement levels are not yet supported");
      known[a] = false;
      continue;
    }
    if (!std::isfinite(m.origin[a]))
      fail("mesh: origin" + axis(a) + " = " + short_number(m.origin[a]) + " is not finite");
    if (!m.coords[a]) {
      const double s = m.spacing[a];
      if (!std::isfinite(s) || !(s > 0.0))
        fail("mesh: spacing" + axis(a) + " = " + short_number(s) + ", must be finite and > 0 (a uniform axis)");
      if (s < kMinSpacing || s > kMaxSpacing)
        fail("mesh: spacing" + axis(a) + " = " + short_number(s) + " is outside [1e-100, 1e100]");
      lo[a] = m.origin[a];
      hi[a] = m.origin[a] + static_cast<double>(m.global_dims[a] - (cell_data(m) ? 0 : 1)) * s;
      smallest(s, a, -1);
      continue;
    }
    if (m.nlevels > 1)
      fail("mesh: coords" + axis(a) + " is set (a rectilinear axis) with nlevels = " + std::to_string(m.nlevels) +
           ": rectilinear axes with refinement levels (AMR) are not yet supported; give axis " +
           std::string(1, kAxis[a]) + " a uniform spacing");
    const double* c = m.coords[a];
    const std::int64_t n = coord_count(m, a);
    for (std::int64_t q = 0; q < n; ++q) {
      if (!std::isfinite(c[q]))
        fail("mesh: coords" + axis(a) + "[" + std::to_string(q) + "] = " + short_number(c[q]) + " is not finite");
      if (q > 0 && !(c[q] > c[q - 1]))
        fail("mesh: coords" + axis(a) + "[" + std::to_string(q) + "] = " + short_number(c[q]) +
             " is not greater than coords" + axis(a) + "[" + std::to_string(q - 1) + "] = " + short_number(c[q - 1]) +
             " (coordinates must be strictly increasing)");
      if (q > 0) smallest(c[q] - c[q - 1], a, q);
    }
    lo[a] = c[0];
    hi[a] = c[n - 1];
  }
  // Within 2^40 smallest spacings of 0 (loop_bounds.h), as tessera_grid; with levels, the
  // finest level's spacing
  h /= static_cast<double>(finest);
  if (std::isfinite(h))
    for (int a = 0; a < 3; ++a)
      if (known[a] && !(std::fabs(lo[a]) <= kMaxCoordinateVoxels * h && std::fabs(hi[a]) <= kMaxCoordinateVoxels * h))
        fail("mesh: along " + std::string(1, kAxis[a]) + " it spans [" + short_number(lo[a]) + ", " +
             short_number(hi[a]) + "], beyond 2^40 times the mesh's smallest spacing from 0 (" +
             short_number(kMaxCoordinateVoxels * h) + "; the smallest spacing, " + short_number(h) + ", is " + h_where +
             (finest > 1 ? " / " + std::to_string(finest) + " at the finest level" : std::string()) +
             "), where a double no longer resolves an element");
}

std::int64_t level_extent(const tessera_mesh& mesh, int level, int a) {
  std::int64_t r = 1;
  for (int l = 0; l < level; ++l) r *= mesh.refinement[l];
  return cell_data(mesh) ? mesh.global_dims[a] * r : (mesh.global_dims[a] - 1) * r + 1;
}

bool mesh_valid(const tessera_mesh* mesh) noexcept {
  if (!mesh) return false;
  try {
    check_mesh(*mesh);
    return true;
  } catch (...) {
    return false;
  }
}

tessera_mesh mesh_for(const tessera_mesh& mesh, bool cells, std::string_view field) {
  tessera_mesh seen = mesh;
  if (cells == cell_data(mesh)) return seen;
  seen.association = cells ? TESSERA_CELL : TESSERA_VERTEX;
  for (int a = 0; a < 3; ++a) {
    seen.global_dims[a] = mesh.global_dims[a] + (cells ? -1 : 1);
    if (seen.global_dims[a] < 1)
      fail("field '" + std::string(field) + "' is cell data, but the mesh has 1 vertex along " +
           std::string(1, kAxis[a]) + " (global_dims" + axis(a) + " = 1): no cell to hold a value");
  }
  return seen;
}

void set_geometry(FieldBinding& b, const tessera_mesh& seen) {
  for (int a = 0; a < 3; ++a) {
    b.placement.global_dims[a] = seen.global_dims[a];
    b.placement.offset[a] = 0;
  }
  // Geometry, passed through: a rectilinear axis' origin and spacing are its first
  // coordinate and its mean spacing (for what reads them; the renderer uses the coordinates)
  const bool cells = cell_data(seen);
  b.geometry.association = cells ? Association::Cell : Association::Vertex;
  Vec3 lo, hi;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t n = seen.global_dims[a];
    const double* c = seen.coords[a];
    b.geometry.coords[a] = c;
    if (c) {
      const std::int64_t m = coord_count(seen, a);
      b.geometry.origin[a] = c[0];
      b.geometry.spacing[a] = m > 1 ? (c[m - 1] - c[0]) / static_cast<double>(m - 1) : 1.0;
      lo[a] = c[0];
      hi[a] = c[m - 1];
    } else {
      b.geometry.origin[a] = seen.origin[a];
      b.geometry.spacing[a] = seen.spacing[a];
      lo[a] = seen.origin[a];
      hi[a] = seen.origin[a] + static_cast<double>(n - (cells ? 0 : 1)) * seen.spacing[a];
    }
  }
  b.global_bounds = Bounds{lo, hi};
}

FieldBinding bind_domains(const tessera_mesh* mesh, const tessera_domain* domains, std::int64_t ndomains,
                          const std::string& field_name, const std::string& render_name) {
  if (!mesh) fail("mesh descriptor is NULL");
  check_mesh(*mesh);
  if (mesh->axes_from_domains)
    fail("mesh: the axes the domains give in pieces (axes_from_domains) were not assembled: another rank's mesh "
         "failed its checks");
  if (ndomains < 0 || ndomains > TESSERA_MAX_DOMAINS)
    fail("ndomains = " + std::to_string(ndomains) + ", must be in [0, " + std::to_string(TESSERA_MAX_DOMAINS) +
         "] (TESSERA_MAX_DOMAINS)");
  if (ndomains > 0 && !domains) fail("domains is NULL with ndomains = " + std::to_string(ndomains));

  FieldBinding b;
  b.domains = true;
  b.nlevels = mesh->nlevels;
  for (int l = 0; l + 1 < mesh->nlevels; ++l) b.refinement[l] = mesh->refinement[l];
  set_geometry(b, *mesh);
  if (ndomains == 0) return b;  // the mesh's association (the ranks with domains tell the field's)

  // Domain 0's field list, sorted by name: every domain must publish the same
  const auto list_of = [&](const tessera_domain& d, std::int64_t index) {
    const std::string who = "domain " + std::to_string(index);
    if (d.level < 0 || d.level >= mesh->nlevels)
      fail(who + ": level " + std::to_string(d.level) + " is outside [0, " + std::to_string(mesh->nlevels) +
           ") (the mesh's nlevels = " + std::to_string(mesh->nlevels) + ")");
    if (d.nfields < 0 || (d.nfields > 0 && !d.fields))
      fail(who + ": field list is invalid (fields = " + std::string(d.fields ? "non-null" : "NULL") +
           ", nfields = " + std::to_string(d.nfields) + ")");
    std::vector<std::pair<std::string_view, int>> list;
    list.reserve(static_cast<std::size_t>(d.nfields));
    for (int f = 0; f < d.nfields; ++f) {
      if (!d.fields[f].name) fail(who + ": fields[" + std::to_string(f) + "]: name is null");
      list.emplace_back(d.fields[f].name, f);
    }
    std::sort(list.begin(), list.end());
    for (std::size_t q = 1; q < list.size(); ++q)
      if (list[q].first == list[q - 1].first)
        fail(who + ": field '" + std::string(list[q].first) + "' is published twice (fields[" +
             std::to_string(list[q - 1].second) + "] and fields[" + std::to_string(list[q].second) + "])");
    return list;
  };
  const auto first = list_of(domains[0], 0);
  const tessera_domain& d0 = domains[0];
  const std::span<const tessera_field> fields0(d0.fields, static_cast<std::size_t>(d0.nfields));
  const int chosen = find_field(fields0, field_name, render_name);
  const std::string name = fields0[static_cast<std::size_t>(chosen)].name;
  // The render's field as its own association sees the mesh (vertex data on a cell mesh, say)
  const bool cells = field_association(*mesh, d0, chosen, "domain 0") == TESSERA_CELL;
  const tessera_mesh seen = mesh_for(*mesh, cells, name);
  set_geometry(b, seen);

  b.blocks.reserve(static_cast<std::size_t>(ndomains));
  for (std::int64_t n = 0; n < ndomains; ++n) {
    const tessera_domain& d = domains[n];
    const std::string who = "domain " + std::to_string(n);
    const auto list = n == 0 ? first : list_of(d, n);
    // The same names and dtypes as domain 0 (both lists sorted by name)
    for (std::size_t q = 0; q < std::max(list.size(), first.size()); ++q) {
      if (q >= list.size() || q >= first.size() || list[q].first != first[q].first) {
        const bool missing = q >= list.size() || (q < first.size() && first[q].first < list[q].first);
        const std::string_view which = missing ? first[q].first : list[q].first;
        fail(who + ": field '" + std::string(which) +
             (missing ? "' is missing: domain 0 publishes it" : "' is not published by domain 0") +
             " (every domain must publish the same fields)");
      }
      const tessera_field& f = d.fields[list[q].second];
      const tessera_field& f0 = d0.fields[first[q].second];
      if (f.dtype != f0.dtype)
        fail(who + ": " + field_label(f) + " has dtype " + dtype_text(f.dtype) + ", domain 0's has " +
             dtype_text(f0.dtype) + " (every domain must publish the same dtypes)");
      const int assoc = field_association(*mesh, d, list[q].second, who);
      if (assoc != field_association(*mesh, d0, first[q].second, "domain 0"))
        fail(who + ": " + field_label(f) + " is " + association_text(assoc) + ", domain 0's is " +
             association_text(1 - assoc) + " (every domain must give a field the same association)");
    }
    // Every published field's descriptors, rendered or not (a wrong one is found at the
    // first call that renders, not when a render first draws it); the render's is kept
    for (const auto& [field_name_q, index] : list) {
      const tessera_field& f = d.fields[index];
      const std::string label = who + ": " + field_label(f);
      const bool own_cells = field_association(*mesh, d, index, who) == TESSERA_CELL;
      const tessera_mesh& fm = own_cells == cells ? seen : mesh_for(*mesh, own_cells, f.name);
      FieldBlock block;
      block.view = bind_array(f, label, own_cells);
      block.domain = static_cast<int>(n);
      block.level = d.level;
      for (int a = 0; a < 3; ++a) {
        block.offset[a] = d.offset[a];
        const std::int64_t extent = level_extent(fm, d.level, a);
        if (d.offset[a] < 0 || block.view.dims[a] > extent - d.offset[a])
          fail(label + ": real " + (own_cells ? "cells [" : "vertices [") + std::to_string(d.offset[a]) + ".." +
               sum_text(d.offset[a], block.view.dims[a]) + ") along " + std::string(1, kAxis[a]) + " (offset" +
               axis(a) + " = " + std::to_string(d.offset[a]) + ") leave " +
               (d.level == 0 ? std::string("the mesh's") : "level " + std::to_string(d.level) + "'s") + " [0.." +
               std::to_string(extent) + ")");
      }
      if (field_name_q == name) b.blocks.push_back(block);
    }
  }
  // Largest first: distributed mode reads the first in place
  std::stable_sort(b.blocks.begin(), b.blocks.end(), [](const FieldBlock& x, const FieldBlock& y) {
    return x.view.vertex_count() > y.view.vertex_count();
  });
  b.local = b.blocks[0].view;
  for (int a = 0; a < 3; ++a) b.placement.offset[a] = b.blocks[0].offset[a];
  return b;
}

}  // namespace tessera::insitu
