#pragma once
/// Every rank's curvilinear and unstructured domains on every rank (replicated mode): each
/// rank packs its checked domains (mesh_binding.h, check_mesh) densely into bytes, the ranks
/// exchange them (ParallelContext::allgather_bytes, within a byte cap), and each rank reads
/// the whole mesh back as views of the received bytes. The core's image does not depend on
/// the order of the domains, so rank order is as good as any.
#include <tessera/mesh.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tessera::insitu {

/// The packed bytes of `mesh`'s domains (each checked by check_mesh): per domain a header,
/// then x, y, z, the connectivity (unstructured), the field's values and the ghost mask, each
/// dense and padded to 8 bytes.
std::string pack_mesh(const Mesh& mesh);

/// The packed size of `mesh` without packing it (to check a limit before allocating).
std::uint64_t packed_mesh_bytes(const Mesh& mesh);

/// The whole mesh: views into `parts` (every rank's pack_mesh, which must outlive the result).
/// Throws std::invalid_argument naming the rank for bytes that are not a packed mesh.
Mesh unpack_meshes(const std::vector<std::string>& parts);

/// The packed bytes of `mesh`'s field values alone (per domain its dtype, count and
/// association, then the values, dense and padded): what moves when every rank's geometry is
/// the one the ranks exchanged last.
std::string pack_values(const Mesh& mesh);

/// The whole mesh of the geometry in `parts` (every rank's pack_mesh of an earlier exchange)
/// with the field values of `values` (every rank's pack_values now, in the same rank order):
/// views into both, which must outlive the result. Throws std::invalid_argument naming the
/// rank for bytes that are not packed values or that do not fit that rank's domains (another
/// domain count, or a count that is neither the domain's vertices nor its cells).
Mesh unpack_with_values(const std::vector<std::string>& parts, const std::vector<std::string>& values);

}  // namespace tessera::insitu
