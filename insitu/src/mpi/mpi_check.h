#pragma once
/// check(): an MPI return code -> std::runtime_error naming the call and MPI's message. For
/// communicators whose error handler is MPI_ERRORS_RETURN (the contexts set it).
#include <mpi.h>

#include <stdexcept>
#include <string>

namespace tessera::insitu::detail {

inline void check(int rc, const char* call) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw std::runtime_error(std::string(call) + " failed: " + std::string(text, len));
}

}  // namespace tessera::insitu::detail
