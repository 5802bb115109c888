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

}  // namespace tessera
