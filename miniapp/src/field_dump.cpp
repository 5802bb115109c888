#include "field_dump.h"

#include <mpi.h>

#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
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

void dump_field(const CartDecomposition& decomp, const HeatSimulation& solver, const std::string& path) {
  static_assert(std::endian::native == std::endian::little, "raw dumps are little-endian");
  const Index3& g = decomp.global_dims();
  const Index3& own = decomp.owned();
  const Index3& off = decomp.offset();
  // This rank's owned block as float32, i fastest.
  const std::vector<double> values = solver.owned_values();
  std::vector<float> block(values.size());
  for (std::size_t n = 0; n < values.size(); ++n) block[n] = static_cast<float>(values[n]);

  // MPI wants C order (slowest first): k, j, i.
  const int sizes[3] = {static_cast<int>(g[2]), static_cast<int>(g[1]), static_cast<int>(g[0])};
  const int sub[3] = {static_cast<int>(own[2]), static_cast<int>(own[1]), static_cast<int>(own[0])};
  const int start[3] = {static_cast<int>(off[2]), static_cast<int>(off[1]), static_cast<int>(off[0])};
  MPI_Datatype view;
  MPI_Type_create_subarray(3, sizes, sub, start, MPI_ORDER_C, MPI_FLOAT, &view);
  MPI_Type_commit(&view);
  const int count = static_cast<int>(block.size());
  const MPI_Offset expected = static_cast<MPI_Offset>(g[0] * g[1] * g[2]) * MPI_Offset(sizeof(float));

  // One temporary name for all ranks (rank 0's pid), next to the file: renamed into place only
  // when every rank's block is written, so a full disk never leaves a truncated dump
  int rank = 0;
  MPI_Comm_rank(decomp.comm(), &rank);
  long pid = rank == 0 ? static_cast<long>(::getpid()) : 0;
  MPI_Bcast(&pid, 1, MPI_LONG, 0, decomp.comm());
  const std::string tmp = path + ".tmp." + std::to_string(pid);

  // Write: every result checked (the status's count too: a short write is a failure)
  std::string fault;
  MPI_File file;
  int rc = MPI_File_open(decomp.comm(), tmp.c_str(), MPI_MODE_CREATE | MPI_MODE_EXCL | MPI_MODE_WRONLY, MPI_INFO_NULL,
                         &file);
  const bool opened = rc == MPI_SUCCESS;
  if (!opened) fault = mpi_error(rc);
  if (opened) {
    rc = MPI_File_set_view(file, 0, MPI_FLOAT, view, "native", MPI_INFO_NULL);
    MPI_Status status;
    if (rc == MPI_SUCCESS) rc = MPI_File_write_all(file, block.data(), count, MPI_FLOAT, &status);
    int written = 0;
    if (rc != MPI_SUCCESS) fault = mpi_error(rc);
    else if (MPI_Get_count(&status, MPI_FLOAT, &written) != MPI_SUCCESS || written != count)
      fault = "short write: " + std::to_string(written) + " of " + std::to_string(count) + " values";
    rc = MPI_File_close(&file);
    if (fault.empty() && rc != MPI_SUCCESS) fault = mpi_error(rc);
  }
  MPI_Type_free(&view);

  // Every rank agrees; rank 0 renames (or removes) the temporary file and reports the rename
  int ok = fault.empty() ? 1 : 0, all_ok = 0;
  MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, decomp.comm());
  int renamed = 0;
  if (rank == 0) {
    // Closed on every rank: the whole file is visible here; its size must be the field's
    struct stat st {};
    if (all_ok && (::stat(tmp.c_str(), &st) != 0 || st.st_size != expected)) {
      all_ok = 0;
      fault = "the written file has " + std::to_string(st.st_size) + " bytes, expected " + std::to_string(expected);
    }
    if (all_ok && std::rename(tmp.c_str(), path.c_str()) == 0) renamed = 1;
    else if (all_ok) fault = std::string("cannot rename '") + tmp + "' into place: " + std::strerror(errno);
    if (!renamed && opened) std::remove(tmp.c_str());
  }
  MPI_Bcast(&renamed, 1, MPI_INT, 0, decomp.comm());
  if (!renamed)
    throw std::runtime_error("--dump " + path + ": " + (fault.empty() ? std::string("failed on another rank") : fault));
}

}  // namespace heat
