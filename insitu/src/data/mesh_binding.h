#pragma once
/// From tessera_execute_mesh_domains' descriptors (tessera.h: tessera_mesh_domain) to core
/// Mesh views (mesh.h) of this rank's curvilinear and unstructured domains for one render's
/// field: read in place, nothing copied. Only the descriptors are read here; check_mesh (which
/// reads the coordinates and indices) runs after, in the pass, once arrays in GPU memory are
/// copied to the host (mesh_staging.h).
///
/// Every function throws std::invalid_argument with a message that names the domain (its
/// index in the call) and the field (TESSERA_ERROR_DATA at the adapter boundary).
#include "data/device_arrays.h"

#include <tessera/mesh.h>
#include <tessera/tessera.h>

#include <cstdint>
#include <string>

namespace tessera::insitu {

struct MeshBinding {
  Mesh local;                                     ///< this rank's domains, in the call's order (may be none)
  std::string field;                              ///< the simulation's name of the bound field
  DType dtype = DType::Float32;                   ///< the field's dtype (the domains agree)
  Association association = Association::Vertex;  ///< the field's (the domains agree)
  std::int64_t cells = 0;                         ///< this rank's cells, ghosts included
  std::int64_t vertices = 0;                      ///< this rank's vertices
  bool gpu_readable = false;                      ///< some array was device or managed memory
  HostStaging staging;                            ///< host copies of its device arrays (mesh_staging.h)
  bool resident = false;  ///< read on the device where it is, nothing staged (mesh_pass.cpp; local.device)
  /// Several ranks, every array device memory, the geometry that of the last full exchange
  /// (promised, or found the same by its hash on the device): only the values and ghost masks
  /// were staged; `local`'s coordinates and connectivity still point at device memory, which
  /// the host must not read (mesh_pass.cpp stages them too if the ranks exchange the geometry)
  bool geometry_on_device = false;
  MeshChecked checked;        ///< the receipt of the pass's check of `local` (for prepare: not checked twice)
  MeshGeometryHash geometry;  ///< the hash of `local`'s geometry, where `hashed` (mesh_pass.cpp)
  bool hashed = false;
};

/// Binds field `field_name` ("" = the only published field) of `domains` (n of them, n in
/// [0, TESSERA_MAX_DOMAINS]; NULL only with n = 0) for render `render_name`. Every domain
/// publishes the same field names and dtypes, and the same association; the field is one
/// array (1-D, or i, j, k consecutive in memory) with no ghost layers; a ghost_field names a
/// uint8 field of the domain.
MeshBinding bind_mesh_domains(const tessera_mesh_domain* domains, std::int64_t n, const std::string& field_name,
                              const std::string& render_name);

}  // namespace tessera::insitu
