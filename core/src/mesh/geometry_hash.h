#pragma once
/// The per-item part of mesh_geometry_hash (mesh.h), for the host's pass (geometry_hash.cpp)
/// and a device's (cuda/mesh_device.h) alike: every geometry item (a coordinate, a
/// connectivity entry, a ghost flag) mixed with its array's tag and its index into two
/// independent 64-bit values, which are summed (mod 2^64): no order, so any split over threads
/// or a GPU's blocks gives the same sums. The host then adds the descriptors (counts, dims,
/// shapes, dtypes) as items of their own. Each mixer is a bijection of its key, so one
/// changed item always changes both sums; several cancel by accident with odds of about
/// 2^-64 per sum. Host and device code (host_device.h).
#include <tessera/host_device.h>
#include <tessera/mesh.h>

#include <cstdint>
#include <vector>

namespace tessera {

/// One array of the geometry: `count` items of `size` bytes (1, 4 or 8), `stride` bytes apart.
struct GeometryArray {
  const unsigned char* base = nullptr;
  std::int64_t count = 0, stride = 0;
  int size = 8;
  std::uint64_t tag = 0;  ///< domain and slot
};

/// The two item sums.
struct GeometrySums {
  std::uint64_t a = 0, b = 0;
};

/// Item i of `g`, zero-extended.
TESSERA_HOST_DEVICE inline std::uint64_t geometry_item(const GeometryArray& g, std::int64_t i) {
  const unsigned char* p = g.base + i * g.stride;
  if (g.size == 8) {
    std::uint64_t x;
    __builtin_memcpy(&x, p, 8);
    return x;
  }
  if (g.size == 4) {
    std::uint32_t x;
    __builtin_memcpy(&x, p, 4);
    return x;
  }
  return *p;
}

/// Adds item i (value x) of the array tagged `tag` to s: a splitmix64 finaliser for a and a
/// murmur3 finaliser of another key for b.
TESSERA_HOST_DEVICE inline void add_geometry_item(GeometrySums& s, std::uint64_t tag, std::uint64_t i,
                                                  std::uint64_t x) {
  std::uint64_t k = x ^ (i * 0x9e3779b97f4a7c15ull) ^ (tag * 0xd6e8feb86659fd93ull);
  k = (k ^ (k >> 30)) * 0xbf58476d1ce4e5b9ull;
  k = (k ^ (k >> 27)) * 0x94d049bb133111ebull;
  s.a += k ^ (k >> 31);
  std::uint64_t h = (x + 0x632be59bd9b4e019ull) ^ ((i + tag * 0x85ebca6bull) * 0xc2b2ae3d27d4eb4full);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  s.b += h ^ (h >> 33);
}

/// The geometry arrays of `mesh` (descriptors accepted by check_mesh_descriptors): per domain
/// x, y, z, the connectivity (unstructured) and the ghost mask (when set).
std::vector<GeometryArray> geometry_arrays(const Mesh& mesh);

/// `mesh` with only its ghost masks left for geometry_arrays (the coordinates' and the
/// connectivity's counts set to 0, the arrays' addresses kept): its item sums are those of the
/// masks alone, tagged as in the whole mesh's. For a layout's record of the masks it was built
/// over (MeshLayout::ghost_sums), compared on the device where a promise skips the hash.
Mesh ghost_masks_only(const Mesh& mesh);

/// Whether any domain of `mesh` has a ghost mask.
bool has_ghost_masks(const Mesh& mesh);

/// The item sums of every array of geometry_arrays(mesh), read as host memory, over TBB's
/// threads (the host's hash, and the emulated device's).
GeometrySums geometry_sums(const Mesh& mesh);

/// The hash from the item sums of every array of geometry_arrays(mesh), the descriptors
/// mixed in as items of their own tag.
MeshGeometryHash finish_geometry_hash(const Mesh& mesh, const GeometrySums& items);

}  // namespace tessera
