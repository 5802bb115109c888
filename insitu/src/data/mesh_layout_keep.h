#pragma once
/// What the adapter keeps of a curvilinear or unstructured mesh between execute calls: the
/// layout its last prepare built (core's MeshLayout: the elements' canonical order, boxes and
/// location lists, which depend on the geometry alone) and the simulation's promise
/// (tessera_mesh_unchanged) that the next call's geometry is the same, or the hash of the
/// geometry it was built over, which finds the same geometry unpromised. The ranks agree on
/// reusing it once per call, at its first render over the mesh (mesh_pass.cpp); within a call
/// every later render reuses the first one's layout (the same domains, so no promise needed).
#include <tessera/render.h>
#include <tessera/scene.h>

#include <memory>

namespace tessera::insitu {

struct MeshLayoutKeep {
  std::shared_ptr<const MeshLayout> layout;  ///< the last mesh render's
  Bounds bounds;                             ///< that render's mesh bounds (every rank's vertices)
  /// The hash of this rank's geometry that `layout` was built over (mesh_geometry_hash, or
  /// cuda_mesh_geometry_hash of a device mesh: the same value), so that the same geometry is
  /// found without the promise
  MeshGeometryHash geometry;
  bool geometry_known = false;
  bool marked = false;    ///< tessera_mesh_unchanged since the last mesh call
  bool carried = false;   ///< this call: it was marked when the call began
  bool detected = false;  ///< this call: this rank's geometry hashes as `layout`'s (no promise needed)
  bool decided = false;   ///< this call: the ranks have agreed on reusing

  /// At each mesh call: the promise (if made) applies to this call, and is spent.
  void begin_call() {
    carried = marked;
    marked = false;
    detected = false;
    decided = false;
  }
  /// This rank holds the layout's geometry: promised, or found the same by its hash.
  bool same_geometry() const { return carried || detected; }
};

}  // namespace tessera::insitu
