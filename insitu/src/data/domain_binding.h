#pragma once
/// From tessera_execute_domains' descriptors (tessera_mesh, tessera_domain) to a validated
/// FieldBinding (field_binding.h): every block this rank holds of the render's field, read in
/// place, with the mesh's geometry (association, origin, spacing, rectilinear coordinates)
/// passed through to the renderer's VolumeGeometry unchanged.
///
/// Nothing here reads field values; a rectilinear axis' coordinates are read (to check them).
/// Every function throws std::invalid_argument with a message naming the domain, field and
/// axis (the caller adds the rank): TESSERA_ERROR_DATA at the adapter boundary. How the
/// blocks of all ranks fit together (overlaps, gaps) is checked later, on every rank alike,
/// by the parallel context (block_layout.h).
#include "data/field_binding.h"

#include <tessera/tessera.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace tessera::insitu {

/// The mesh alone: association 0 or 1; nlevels in [1, kMaxAmrLevels] (amr.h); with
/// nlevels > 1 refinement non-null, its nlevels - 1 ratios each 2 or 4, and no rectilinear
/// axis ("not yet"); global_dims in [1, INT_MAX]; origin finite; a uniform axis' spacing
/// finite and in [1e-100, 1e100]; a rectilinear axis' global_dims[a] (vertex) or
/// global_dims[a] + 1 (cell) coordinates finite and strictly increasing; the mesh within 2^40
/// smallest spacings (of the finest level) of 0.
void check_mesh(const tessera_mesh& mesh);

/// Elements of level `level` along axis a of a valid mesh (AmrField::level_dims): vertex data
/// (global_dims - 1) R + 1, cell data global_dims R, R the product of the level's ratios.
std::int64_t level_extent(const tessera_mesh& mesh, int level, int a);

/// check_mesh without throwing.
bool mesh_valid(const tessera_mesh* mesh) noexcept;

/// The mesh as a field of the given association sees it: the same points and cells, counted
/// as vertices (cells + 1 per axis) or as cells (vertices - 1); origin, spacing and coordinates
/// unchanged. `mesh` itself when the associations agree. Throws (naming `field`) for cell data
/// on a mesh with one vertex along an axis.
tessera_mesh mesh_for(const tessera_mesh& mesh, bool cells, std::string_view field);

/// The binding's geometry and global placement from the mesh as its field sees it (mesh_for).
void set_geometry(FieldBinding& b, const tessera_mesh& seen);

/// Binds the render's field (`field_name`, or the only published field when empty) of every
/// domain: domains non-null when ndomains > 0; 0 <= ndomains <= TESSERA_MAX_DOMAINS; each
/// domain at a level in [0, nlevels) with a valid field list (non-null when nfields > 0, names non-null and
/// distinct) publishing the same names, dtypes and associations as domain 0 (a domain's
/// associations, or the mesh's for every field without them); the geometry is the mesh as the
/// render's field sees it (mesh_for); every published field's array
/// valid (bind_array) and its real elements inside its level's extent (level_extent), the
/// render's field or not (descriptors only: no value is read). How the levels
/// nest is checked later, with every rank's boxes (amr_layout.h). Blocks come largest first (ties in
/// domain order). A rank without domains gets no blocks (local.data null, dtype unknown).
FieldBinding bind_domains(const tessera_mesh* mesh, const tessera_domain* domains, std::int64_t ndomains,
                          const std::string& field_name, const std::string& render_name);

}  // namespace tessera::insitu
