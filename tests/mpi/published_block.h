#pragma once
/// The MPI adapter tests' common input: this rank's block of a global field of blobs, held as a
/// simulation holds it (float32, one ghost layer on every side) and described by the C API's
/// tessera_field and tessera_grid; and each rank's config file.
#include "mpi_test_support.h"

#include <tessera/tessera.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <string>

namespace tessera_mpi_test {

struct PublishedBlock {
  PublishedBlock(const Box& box, const std::array<std::int64_t, 3>& global)
      : local(box, tessera::DType::Float32, Layout::COrder, blobs(global)) {
    const tessera::FieldView real = local.view();
    field.name = "density";
    field.dtype = TESSERA_FLOAT32;
    for (int a = 0; a < 3; ++a) {
      field.dims[a] = box.dims[a] + 2;
      field.byte_strides[a] = real.byte_strides[a];
      field.ghosts_lo[a] = field.ghosts_hi[a] = 1;
      grid.origin[a] = -0.5;
      grid.spacing[a] = 1.0 / static_cast<double>(global[a] - 1);
      grid.global_dims[a] = global[a];
      grid.offset[a] = box.offset[a];
    }
    // data: element (0,0,0) of the array, ghosts included
    field.data = static_cast<const unsigned char*>(real.data) - real.byte_strides[0] - real.byte_strides[1] -
                 real.byte_strides[2];
  }
  LocalArray local;
  tessera_field field{};
  tessera_grid grid{};
};

/// Writes this rank's config (rank r: cfg_r.yaml in `dir`) and returns its path; collective
/// (a barrier), so every rank's file exists when it returns.
inline std::string write_rank_config(const SharedTempDir& dir, const std::string& text) {
  const std::string path = dir.file("cfg_" + std::to_string(world_rank()) + ".yaml");
  std::ofstream(path) << text;
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

}  // namespace tessera_mpi_test
