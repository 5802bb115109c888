#pragma once
/// mesh_summary: the macrocell value ranges of a mesh, as the FieldSummary that the majorant
/// grid derives its majorants from (field/majorant_grid.h), over the grid that MeshTables lays
/// over the mesh's box.
///
/// Each macrocell (edge E voxels of that grid, cells as FieldSummary's for its dims) gets the
/// union of the value ranges (min / max of the vertex values, or the cell value, with the
/// NaN / Inf flags) of every element whose box, padded by 1e-6 voxels, meets the cell. A
/// barycentric or trilinear value clamped to its element is a convex combination of the
/// element's vertex values, so it never leaves that range: the majorant is never below the
/// field anywhere in the cell. A cell that no element meets is empty (majorant 0).
#include <tessera/field_summary.h>

#include "mesh/mesh_tables.h"

#include <memory>

namespace tessera {

std::shared_ptr<const FieldSummary> mesh_summary(const MeshTables& tables, int edge);

/// Share `share` of `shares` (0 <= share < shares) of mesh_summary's parts: the elements among
/// the input's cells [C share / shares, C (share + 1) / shares) (C: every domain's cells, in
/// order) and the value totals of the values [V share / shares, ...) (V: every domain's field
/// count), the cells not met left empty. The shares combined (element-wise min of lo, max of
/// hi, or of flags, sums of nan and elements, min of vmin, max of vmax: in any order) are
/// mesh_summary's parts bit for bit: ranks holding the same mesh each summarise a share.
FieldSummary::Parts mesh_summary_share(const MeshTables& tables, int edge, int share, int shares);
/// The summary of combined shares (mesh_summary_share) of tables over `layout` for `edge`;
/// parts of another cell count are refused by name.
std::shared_ptr<const FieldSummary> mesh_summary_of(FieldSummary::Parts&& parts, const MeshLayout& layout, int edge);

/// The macrocells with edge `edge` (>= 1) over the grid of `geometry` with `dims` vertices per
/// axis (MeshTables' grid) that mesh_summary fills.
MacroGrid macro_grid(const VolumeGeometry& geometry, const std::int64_t* dims, int edge);

/// Empty macrocells of `g` (lo +Inf, hi -Inf, no flag) in a Parts (cells set, nothing else).
FieldSummary::Parts empty_cells(const MacroGrid& g);
/// Folds range `r` of an element with box `box` into every macrocell of `g` the box meets.
void fold_into_cells(FieldSummary::Parts& parts, const MacroGrid& g, const double* box, const ElementRange& r);

}  // namespace tessera
