#pragma once
/// BlobSlab: this rank's slab of a blob field for the adapter's MPI tests (limits, device).
#include "mpi_test_support.h"

#include <tessera/tessera.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace tessera_mpi_test {

/// This rank's slab (along k) of a blob of integer values in [0, 250] on n^3 vertices over the
/// unit cube, as a float32 tessera_field named "density" and its grid.
struct BlobSlab {
  explicit BlobSlab(int n = 16) {
    const int r = world_rank(), size = world_size();
    k0 = n * r / size;
    nk = n * (r + 1) / size - k0;
    values.resize(static_cast<std::size_t>(n) * n * nk);
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double x = i / (n - 1.0) - 0.5, y = j / (n - 1.0) - 0.5, z = (k0 + k) / (n - 1.0) - 0.5;
          values[i + n * (j + static_cast<std::size_t>(n) * k)] =
              static_cast<float>(std::round(250.0 * std::exp(-(x * x + y * y + z * z) / 0.08)));
        }
    field = tessera_field{};
    field.name = "density";
    field.data = values.data();
    field.dtype = TESSERA_FLOAT32;
    field.dims[0] = field.dims[1] = n;
    field.dims[2] = nk;
    field.byte_strides[0] = 4;
    field.byte_strides[1] = 4LL * n;
    field.byte_strides[2] = 4LL * n * n;
    grid = tessera_grid{};
    for (int a = 0; a < 3; ++a) {
      grid.spacing[a] = 1.0 / (n - 1);
      grid.global_dims[a] = n;
    }
    grid.offset[2] = k0;
  }
  int k0 = 0, nk = 0;
  std::vector<float> values;
  tessera_field field{};
  tessera_grid grid{};
};

}  // namespace tessera_mpi_test
