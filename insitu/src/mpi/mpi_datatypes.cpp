#include "mpi/mpi_datatypes.h"

#include "mpi/mpi_check.h"

#include <type_traits>

namespace tessera::insitu::detail {

static_assert(std::is_trivially_copyable_v<PixelSums>, "pixels travel as raw bytes");
static_assert(std::is_trivially_copyable_v<AuxSums>, "auxiliary sums travel as raw bytes");

TypeList::~TypeList() {
  for (MPI_Datatype& t : m_types) MPI_Type_free(&t);
}

MPI_Datatype TypeList::commit(MPI_Datatype t) {
  m_types.push_back(t);
  check(MPI_Type_commit(&m_types.back()), "MPI_Type_commit");
  return t;
}

MPI_Datatype element_type(DType t) {
  switch (t) {
    case DType::UInt8: return MPI_UINT8_T;
    case DType::Int16: return MPI_INT16_T;
    case DType::UInt16: return MPI_UINT16_T;
    case DType::Float32: return MPI_FLOAT;
    case DType::Float64:
    default: return MPI_DOUBLE;
  }
}

MPI_Datatype blocks_in_place_type(std::span<const FieldBlock> blocks, TypeList& keep) {
  if (blocks.empty()) return MPI_BYTE;
  std::vector<int> lens(blocks.size(), 1);
  std::vector<MPI_Aint> displs(blocks.size());
  std::vector<MPI_Datatype> types(blocks.size());
  for (std::size_t n = 0; n < blocks.size(); ++n) {
    check(MPI_Get_address(blocks[n].view.data, &displs[n]), "MPI_Get_address");
    types[n] = strided_view_type(blocks[n].view, keep);
  }
  MPI_Datatype t = MPI_DATATYPE_NULL;
  check(MPI_Type_create_struct(static_cast<int>(blocks.size()), lens.data(), displs.data(), types.data(), &t),
        "MPI_Type_create_struct");
  return keep.commit(t);
}

MPI_Datatype strided_view_type(const FieldView& v, TypeList& keep) {
  MPI_Datatype row, plane, box;
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[0]), 1, v.byte_strides[0], element_type(v.dtype), &row),
        "MPI_Type_create_hvector");
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[1]), 1, v.byte_strides[1], row, &plane),
        "MPI_Type_create_hvector");
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[2]), 1, v.byte_strides[2], plane, &box),
        "MPI_Type_create_hvector");
  MPI_Type_free(&row);
  MPI_Type_free(&plane);
  return keep.commit(box);
}

MPI_Datatype replica_box_type(DType dtype, const std::int64_t global[3], const std::int64_t offset[3],
                              const std::int64_t dims[3], TypeList& keep) {
  // MPI_ORDER_C lists the slowest axis first: k, j, i.
  const int sizes[3] = {static_cast<int>(global[2]), static_cast<int>(global[1]), static_cast<int>(global[0])};
  const int sub[3] = {static_cast<int>(dims[2]), static_cast<int>(dims[1]), static_cast<int>(dims[0])};
  const int start[3] = {static_cast<int>(offset[2]), static_cast<int>(offset[1]), static_cast<int>(offset[0])};
  MPI_Datatype t;
  check(MPI_Type_create_subarray(3, sizes, sub, start, MPI_ORDER_C, element_type(dtype), &t),
        "MPI_Type_create_subarray");
  return keep.commit(t);
}

MPI_Datatype pixel_type(TypeList& keep, std::size_t bytes) {
  MPI_Datatype t;
  check(MPI_Type_contiguous(static_cast<int>(bytes), MPI_BYTE, &t), "MPI_Type_contiguous");
  return keep.commit(t);
}

MPI_Datatype tile_rows_type(const std::vector<Tile>& tiles, std::span<const int> indices, int width, MPI_Datatype pixel,
                            TypeList& keep, std::uint64_t& pixels, std::size_t pixel_bytes) {
  std::vector<int> lengths;
  std::vector<MPI_Aint> displs;
  for (int t : indices) {
    const Tile& tile = tiles[t];
    for (int y = tile.y0; y < tile.y1; ++y) {
      lengths.push_back(tile.x1 - tile.x0);
      displs.push_back(static_cast<MPI_Aint>((static_cast<std::int64_t>(y) * width + tile.x0) *
                                             static_cast<std::int64_t>(pixel_bytes)));
      pixels += static_cast<std::uint64_t>(tile.x1 - tile.x0);
    }
  }
  MPI_Datatype t;
  check(MPI_Type_create_hindexed(static_cast<int>(lengths.size()), lengths.data(), displs.data(), pixel, &t),
        "MPI_Type_create_hindexed");
  return keep.commit(t);
}

}  // namespace tessera::insitu::detail
