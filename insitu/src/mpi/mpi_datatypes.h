#pragma once
/// MPI derived datatypes of the MPI context: a simulation's strided view read in place, a box
/// of the C-order replica, whole Film pixels, and the rows of a list of tiles. Each function
/// commits the type it builds and hands it to a TypeList, which frees it at the end of the
/// caller's scope. Errors throw std::runtime_error (mpi_check.h).
#include <tessera/field_view.h>
#include <tessera/film.h>
#include <tessera/tiles.h>

#include "parallel/parallel_context.h"

#include <mpi.h>

#include <cstdint>
#include <span>
#include <vector>

namespace tessera::insitu::detail {

/// Owns committed derived datatypes until the end of a scope.
class TypeList {
 public:
  TypeList() = default;
  TypeList(const TypeList&) = delete;
  TypeList& operator=(const TypeList&) = delete;
  ~TypeList();
  /// Commits `t` and keeps it; returns it.
  MPI_Datatype commit(MPI_Datatype t);

 private:
  std::vector<MPI_Datatype> m_types;
};

/// The MPI type of one element of `t`.
MPI_Datatype element_type(DType t);

/// One element per vertex of a strided view, addressed relative to view.data: nested hvectors
/// over the view's byte strides, so MPI reads the simulation's array in place.
MPI_Datatype strided_view_type(const FieldView& v, TypeList& keep);

/// Every block's elements read in place: one struct type over their absolute addresses (use
/// with MPI_BOTTOM); MPI_BYTE for no block (a count of 0 must go with it).
MPI_Datatype blocks_in_place_type(std::span<const FieldBlock> blocks, TypeList& keep);

/// The sub-box [offset, offset + dims) of the C-order replica of `global` vertices.
MPI_Datatype replica_box_type(DType dtype, const std::int64_t global[3], const std::int64_t offset[3],
                              const std::int64_t dims[3], TypeList& keep);

/// Whole pixels of a Film (PixelSums, or with `bytes` = sizeof(AuxSums) its auxiliary sums
/// for image.denoise), moved as raw bytes (doubles and counters exactly as they are).
MPI_Datatype pixel_type(TypeList& keep, std::size_t bytes = sizeof(PixelSums));

/// The rows of the tiles `indices` inside a width-wide Film, relative to its first pixel, in
/// units of `pixel` (of `pixel_bytes` each: PixelSums, or AuxSums for the auxiliary sums).
/// Adds the number of pixels they cover to `pixels`.
MPI_Datatype tile_rows_type(const std::vector<Tile>& tiles, std::span<const int> indices, int width, MPI_Datatype pixel,
                            TypeList& keep, std::uint64_t& pixels, std::size_t pixel_bytes = sizeof(PixelSums));

}  // namespace tessera::insitu::detail
