#pragma once
/// From the simulation's descriptors (tessera_field, tessera_grid) to a validated, zero-copy
/// tessera::FieldView of this rank's real vertices and its place in the global grid.
///
/// Nothing here reads field memory: validation looks at the descriptors and pointer values
/// only. Every function throws std::invalid_argument with a message that names the field and
/// the fault (TESSERA_ERROR_DATA at the adapter boundary).
#include "data/field_block.h"

#include <tessera/amr.h>
#include <tessera/field_view.h>
#include <tessera/scene.h>
#include <tessera/tessera.h>

#include <cstring>
#include <span>
#include <string>
#include <vector>

namespace tessera::insitu {

/// A field bound for one execute call: valid only during that call.
/// With tessera_execute_domains (domain_binding.h) a rank holds any number of blocks: `local`
/// and `placement.offset` are then its largest block (the one distributed mode reads in
/// place; data null when it holds none), and `blocks` lists them all, largest first.
struct FieldBinding {
  FieldView local;                 ///< this rank's real vertices, in the simulation's memory
  GlobalPlacement placement;       ///< where they sit in the global grid
  VolumeGeometry geometry;         ///< world placement of global vertex (0,0,0) and the spacing
  Bounds global_bounds;            ///< world bounds of the whole domain
  std::vector<FieldBlock> blocks;  ///< every block of this rank (tessera_execute: one, domain -1)
  bool domains = false;            ///< bound from tessera_execute_domains
  /// Refinement levels (tessera_mesh's nlevels, refinement): 1 = a single level; blocks'
  /// FieldBlock::level in [0, nlevels); refinement[l] (2 or 4) takes level l to l + 1.
  int nlevels = 1;
  int refinement[kMaxAmrLevels - 1] = {};
  /// Bytes Tessera allocated to stage the blocks' values (a vector's magnitude,
  /// vector_binding.h), counted against the memory limit; 0 when read in place.
  std::uint64_t staged_bytes = 0;
  /// The blocks are one block covering the whole grid of a single-level mesh (then the field
  /// is read in place on one rank, with no replica).
  bool whole() const;
};

/// Index of the field the render uses: `field_name`, or the only published field when the
/// render names none. Also rejects null or duplicate names among `fields`.
int find_field(std::span<const tessera_field> fields, const std::string& field_name, const std::string& render_name);

/// Validates `field` and `grid` together: dtype in range, data non-null, dims >= 1, ghost
/// widths >= 0 and < dims, strides non-zero, non-overlapping and within the address space,
/// spacing finite and > 0, origin finite, global_dims >= 1, offset >= 0 and real extent +
/// offset <= global_dims.
FieldBinding bind_field(const tessera_field& field, const tessera_grid& grid);

/// The descriptor checks of bind_field (dtype, data, dims, ghosts, strides) without the grid:
/// the view of the field's real elements (ghosts skipped). Messages start with `label` and
/// call an element a cell (`cells`) or a vertex.
FieldView bind_array(const tessera_field& field, const std::string& label, bool cells = false);

/// Throws std::invalid_argument naming `label` (and the block, when several) and the pointer
/// when a block in host memory cannot be read where the render reads it (unreadable_byte,
/// tessera/host_readable.h: freed or unmapped memory, an array smaller than its descriptor,
/// device memory the CUDA runtime does not know). Device and managed memory are not probed.
/// For the rendered field only: the other published fields' descriptors are checked, their
/// memory never touched. One system call per block.
void require_readable(const FieldBinding& b, const std::string& label);

/// The int a C caller stored in an enum member of a descriptor (tessera_dtype, ...), read
/// without assuming it is one of the enum's values: reading an out-of-range value as the enum
/// is undefined behaviour, and any int may arrive from C or Fortran.
template <class E>
int raw_int(const E& e) {
  static_assert(sizeof(E) == sizeof(int));
  int v;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

/// "field 'NAME'" (or "field '(null)'").
std::string field_label(const tessera_field& f);

/// For a single rank: its real vertices must be the whole grid (offset 0, real dims ==
/// global_dims).
void require_whole_grid(const tessera_field& field, const FieldBinding& binding);

}  // namespace tessera::insitu
