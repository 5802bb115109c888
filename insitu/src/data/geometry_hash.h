#pragma once
/// GeometryHash: two independent 64-bit hashes of what a mesh's layout depends on (its
/// domains' dims, shapes, counts and dtypes, every vertex's coordinates, every connectivity
/// entry and every ghost flag; never the values), so that the adapter can tell a call whose
/// geometry is the last one's bit for bit without the simulation's promise
/// (tessera_mesh_unchanged) and reuse the layout. One pass over the geometry's elements, no
/// allocation. Two different mixers, so an accidental match needs a collision in both (about
/// 2^-128); not cryptographic. A false match can only give a wrong image: the indices are
/// still checked (check_mesh_indices), so nothing is read outside the arrays.
#include <tessera/mesh.h>

#include <cstdint>

namespace tessera::insitu {

struct GeometryHash {
  std::uint64_t a = 0, b = 0;
  bool operator==(const GeometryHash&) const = default;
};

/// The hash of `mesh`'s geometry. Its arrays must be host-readable and their descriptors
/// accepted (check_mesh_arrays).
GeometryHash geometry_hash(const Mesh& mesh);

}  // namespace tessera::insitu
