#pragma once
/// Ranks agree on what a firing call publishes (rank_agreement.h carries the record): the grid
/// of tessera_execute, or the mesh and the field list of tessera_execute_domains. One
/// fixed-size record per rank travels in the call's allgather; every rank compares every
/// rank's record with a reference rank's (rank 0 for the grid and mesh; for the fields, the
/// first rank that holds domains) and reaches the same verdict, which names the property that
/// differs, the axis or index at fault and both values:
///   "rank 1's mesh has cell data (TESSERA_CELL), rank 0's vertex data (TESSERA_VERTEX)"
///   "axis j (coords[1]) is rectilinear on rank 1, uniform on rank 0 (spacing 0.1)"
///   "coords[0] (i)[17] is 0.53 on rank 1, 0.5 on rank 0"
///   "field 'pressure' (float64) is published on rank 1 but not on rank 0"
/// Compared: the kind of call; global_dims; per axis uniform or rectilinear; a uniform axis'
/// spacing and origin (doubles bit for bit); a rectilinear axis' coordinates (a hash, then on
/// the failure path only the values of the first differing chunk, bounded: see below); for
/// meshes the association, nlevels and refinement ratios; for domains calls the sorted list of
/// (name, dtype, association) that domain 0 of each rank publishes (every domain of a rank publishes the
/// same: the bind phase checks that), so that a difference between ranks is the same error
/// as a difference between the domains of one rank. A rank without domains publishes no list.
/// A grid or mesh that fails its own checks on some rank is not compared (the bind phase
/// reports it on every rank alike).
#include "parallel/parallel_context.h"

#include <tessera/amr.h>
#include <tessera/tessera.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tessera::insitu {

/// One rank's view of a call's publication (trivially copyable: raw bytes in an allgather).
struct PublicationRecord {
  std::uint64_t domains_call;  ///< 2: tessera_execute_mesh_domains, 1: tessera_execute_domains, 0: tessera_execute
  std::uint64_t has_grid;      ///< the grid or mesh is present and valid
  std::uint64_t origin_bits[3];
  std::uint64_t spacing_bits[3];
  std::int64_t global_dims[3];
  std::int64_t association;  ///< meshes: TESSERA_VERTEX or TESSERA_CELL
  std::int64_t nlevels;
  std::int64_t refinement[kMaxAmrLevels - 1];
  std::uint64_t rectilinear[3];     ///< 1 where coords[a] is set
  std::int64_t axes_from_domains;   ///< meshes: the axes the domains give in pieces
  std::uint64_t coords_hash[3][2];  ///< of a rectilinear axis' values, bit for bit
  std::uint64_t has_fields;         ///< a domains call with domains and a readable field list
  std::uint64_t fields_count;
  std::uint64_t fields_hash[2];  ///< of the sorted (name, dtype, association) list
};

/// This rank's record. grid: tessera_execute's (may be NULL); mesh, domains, ndomains:
/// tessera_execute_domains' (domains_call true; may be NULL or invalid). Reads the coordinates
/// of a rectilinear axis and the names of domain 0's fields (O(n log n) in its fields).
/// The record of a tessera_execute_mesh_domains call: its kind alone (domains_call 2).
PublicationRecord mesh_call_record();

PublicationRecord publication_record(bool domains_call, const tessera_grid* grid, const tessera_mesh* mesh,
                                     const tessera_domain* domains, std::int64_t ndomains);

/// What this rank's call publishes, for the failure path's detail exchanges: the same
/// descriptors as publication_record got.
struct PublicationView {
  const tessera_mesh* mesh = nullptr;
  const tessera_domain* domains = nullptr;
  std::int64_t ndomains = 0;
};

/// Collective only where the records disagree on coordinates or fields (every rank then takes
/// part in at most four broadcasts of at most ~1 MB each, the same on every rank since every
/// rank has every record). `all`: every rank's record, in rank order. Returns the message
/// ("ranks disagree on the grid at step 3: rank 1 has spacing [..], rank 0 has [..] ...") or
/// nothing. Throws only on MPI failure.
std::optional<std::string> publication_disagreement(ParallelContext& ctx, std::int64_t step,
                                                    std::span<const PublicationRecord> all,
                                                    const PublicationView& mine);

}  // namespace tessera::insitu
