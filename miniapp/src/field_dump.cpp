#include "field_dump.h"

#include <mpi.h>

#include <bit>
#include <stdexcept>
#include <vector>

namespace heat {
namespace {

std::string mpi_error(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(code, text, &len);
  return std::string(text, static_cast<std::size_t>(len));
}

}  // namespace

void dump_field(const CartDecomposition& decomp, const HeatSolver& solver, const std::string& path) {
  static_assert(std::endian::native == std::endian::little, "raw dumps are little-endian");
  const Index3& g = decomp.global_dims();
  const Index3& own = decomp.owned();
  const Index3& off = decomp.offset();
  // This rank's owned block as float32, i fastest.
  std::vector<float> block(static_cast<std::size_t>(own[0] * own[1] * own[2]));
  std::size_t n = 0;
  for (std::int64_t k = 0; k < own[2]; ++k)
    for (std::int64_t j = 0; j < own[1]; ++j)
      for (std::int64_t i = 0; i < own[0]; ++i) block[n++] = static_cast<float>(solver.at(i, j, k));

  // MPI wants C order (slowest first): k, j, i.
  const int sizes[3] = {static_cast<int>(g[2]), static_cast<int>(g[1]), static_cast<int>(g[0])};
  const int sub[3] = {static_cast<int>(own[2]), static_cast<int>(own[1]), static_cast<int>(own[0])};
  const int start[3] = {static_cast<int>(off[2]), static_cast<int>(off[1]), static_cast<int>(off[0])};
  MPI_Datatype view;
  MPI_Type_create_subarray(3, sizes, sub, start, MPI_ORDER_C, MPI_FLOAT, &view);
  MPI_Type_commit(&view);
  MPI_File file;
  int rc = MPI_File_open(decomp.comm(), path.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &file);
  if (rc == MPI_SUCCESS) {
    MPI_File_set_size(file, 0);  // an older, longer file must not leave a tail
    rc = MPI_File_set_view(file, 0, MPI_FLOAT, view, "native", MPI_INFO_NULL);
    if (rc == MPI_SUCCESS)
      rc = MPI_File_write_all(file, block.data(), static_cast<int>(block.size()), MPI_FLOAT, MPI_STATUS_IGNORE);
    MPI_File_close(&file);
  }
  MPI_Type_free(&view);
  // Every rank reports the same outcome.
  int worst = rc;
  MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, decomp.comm());
  if (worst != MPI_SUCCESS)
    throw std::runtime_error("--dump " + path + ": " + mpi_error(rc != MPI_SUCCESS ? rc : worst));
}

}  // namespace heat
