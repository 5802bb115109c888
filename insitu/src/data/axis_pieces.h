#pragma once
/// Per-domain rectilinear coordinates (Blueprint's rectilinear coordset per domain) assembled
/// into the mesh's global axes. With bit a of tessera_mesh::axes_from_domains set, each domain
/// may give its piece of axis a (tessera_domain coords[a], coords_start[a], coords_count[a]:
/// vertex coordinates from global level-0 vertex index coords_start[a] on, ghosts allowed).
/// Every rank's pieces travel to every rank (pack_pieces, then ParallelContext::allgather_bytes)
/// and every rank assembles the same axes from them (assemble_axes): each of the axis'
/// vertices covered, overlapping pieces equal bit for bit, indices outside the axis ignored.
#include "data/field_block.h"

#include <tessera/tessera.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace tessera::insitu {

/// The most values one piece may hold beyond its axis' vertices (ghost layers on both sides).
inline constexpr std::int64_t kMaxPieceOverhang = 64;

/// This rank's pieces of the axes in `axes` (bits 1, 2, 4), as bytes for the exchange. A piece
/// whose count is out of [1, vertices + 2 kMaxPieceOverhang] travels without its values, and
/// assemble_axes reports it (so every rank reports it alike). Reads the pieces' values.
std::string pack_pieces(const tessera_mesh& mesh, const tessera_domain* domains, std::int64_t ndomains);

/// The global axes from every rank's packed pieces (in rank order): for each axis in
/// mesh.axes_from_domains, its vertex coordinates (global_dims[a] vertices for vertex data,
/// + 1 for cell data); other axes empty. Throws LayoutError naming the rank, domain, axis and
/// index: two pieces that differ where they overlap, a vertex no piece covers, a piece whose
/// count is out of range or that has no values; a domain that gives no piece is fine.
std::array<std::vector<double>, 3> assemble_axes(const tessera_mesh& mesh, std::span<const std::string> per_rank);

/// The bytes the exchange may carry in all: every vertex of the pieced axes 64 times over
/// (plus headers), at most 1 GiB.
std::size_t max_piece_bytes(const tessera_mesh& mesh);

}  // namespace tessera::insitu
