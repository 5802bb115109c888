#pragma once
/// What the adapter keeps of a curvilinear or unstructured mesh between execute calls: the
/// layout its last prepare built (core's MeshLayout: the elements' canonical order, boxes and
/// location lists, which depend on the geometry alone) and the simulation's promise
/// (tessera_mesh_unchanged) that the next call's geometry is the same, or the hash of the
/// geometry it was built over, which finds the same geometry unpromised. The ranks agree on
/// reusing it once per call, at its first render over the mesh (mesh_pass.cpp); within a call
/// every later render reuses the first one's layout (the same domains, so no promise needed).
#include <tessera/mesh.h>
#include <tessera/render.h>
#include <tessera/scene.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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
  bool carried = false;   ///< this call: promised, and the last call's geometry was `layout`'s
  bool detected = false;  ///< this call: this rank's geometry hashes as `layout`'s (no promise needed)
  bool decided = false;   ///< this call: the ranks have agreed on reusing
  /// Mesh calls so far (every execute over a mesh, whether a render fires or not), and the
  /// last of them whose geometry is known to be `layout`'s (0: none): a promise says "as at
  /// the last call", so it carries the layout only when that call's geometry was the layout's.
  /// A call at which no render fires, with the mesh moved and no promise, breaks the chain.
  std::uint64_t calls = 0, known = 0;
  /// Several ranks: every rank's domains as exchanged when `layout` was built or last reused
  /// after a full exchange (pack_mesh, mesh_exchange.h), and the call that exchanged them. While
  /// every rank holds that geometry, a render exchanges only the values (pack_values) and
  /// reads the geometry from here. Cleared with the layout.
  std::vector<std::string> parts;
  std::uint64_t parts_call = 0;
  /// The receipt of the last check of a mesh read from `parts` (the full exchange's copy, or
  /// a values-only render's), carried to each later values-only render's mesh
  /// (MeshChecked::with_new_values: the geometry is the same bytes) instead of checking those
  /// bytes again. Empty when the full exchange's mesh was checked by prepare itself.
  MeshChecked parts_checked;
  /// The receipt of this rank's last check of its own host arrays (check_local) and the hash
  /// of the geometry it checked: a later call whose geometry hashes the same, in the same arrays,
  /// carries it to its new values (MeshChecked::with_new_values) instead of reading every
  /// index again (the bytes the check read are those bytes, but for a collision of both 64-bit
  /// sums). Kept across layouts; empty until a hashed call's check.
  MeshChecked local_checked;
  MeshGeometryHash local_checked_geometry;

  /// At each mesh call, as it begins (before its triggers): the promise (if made) applies to
  /// this call, and is spent.
  void begin_call() {
    ++calls;
    if (marked && known != 0 && known + 1 == calls) known = calls;
    carried = known == calls;
    marked = false;
    detected = false;
    decided = false;
  }
  /// This call's geometry is `layout`'s: the layout was built or reused over it, or its hash
  /// matched.
  void holds_layout() { known = calls; }
  /// This rank holds the layout's geometry: promised, or found the same by its hash.
  bool same_geometry() const { return carried || detected; }
};

}  // namespace tessera::insitu
