#pragma once
/// Helpers for the MPI tests: agreement on verdicts, sub-communicators of the first n ranks,
/// block decompositions and local arrays in several memory layouts.
#include <tessera/field_view.h>

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace tessera_mpi_test {

inline int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
inline int world_size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

/// A scratch directory named by rank 0, the same path on every rank; removed by rank 0 after
/// a barrier. Collective: every rank constructs and destroys it together.
class SharedTempDir {
 public:
  explicit SharedTempDir(const std::string& prefix = "tessera_mpi_") {
    std::string path;
    if (world_rank() == 0) {
      std::random_device rd;
      path = (std::filesystem::temp_directory_path() / (prefix + std::to_string(rd()) + std::to_string(rd()))).string();
      std::filesystem::create_directories(path);
    }
    int len = static_cast<int>(path.size());
    MPI_Bcast(&len, 1, MPI_INT, 0, MPI_COMM_WORLD);
    path.resize(static_cast<std::size_t>(len));
    MPI_Bcast(path.data(), len, MPI_CHAR, 0, MPI_COMM_WORLD);
    m_path = path;
  }
  ~SharedTempDir() {
    MPI_Barrier(MPI_COMM_WORLD);
    std::error_code ec;
    if (world_rank() == 0) std::filesystem::remove_all(m_path, ec);
  }
  SharedTempDir(const SharedTempDir&) = delete;
  SharedTempDir& operator=(const SharedTempDir&) = delete;

  std::string file(const std::string& name) const { return (std::filesystem::path(m_path) / name).string(); }
  /// Rank 0 writes the file; every rank returns its path after the write (collective).
  std::string write(const std::string& name, const std::string& text) const {
    if (world_rank() == 0) std::ofstream(file(name)) << text;
    MPI_Barrier(MPI_COMM_WORLD);
    return file(name);
  }

 private:
  std::string m_path;
};

/// True on every rank of `comm` iff `ok` on every rank.
inline bool all_ranks(bool ok, MPI_Comm comm = MPI_COMM_WORLD) {
  int local = ok ? 1 : 0, all = 0;
  MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LAND, comm);
  return all != 0;
}

/// The first n ranks of MPI_COMM_WORLD (MPI_COMM_NULL on the others). Collective over world.
class FirstRanks {
 public:
  explicit FirstRanks(int n) {
    MPI_Comm_split(MPI_COMM_WORLD, world_rank() < n ? 0 : MPI_UNDEFINED, world_rank(), &m_comm);
  }
  ~FirstRanks() {
    if (m_comm != MPI_COMM_NULL) MPI_Comm_free(&m_comm);
  }
  FirstRanks(const FirstRanks&) = delete;
  FirstRanks& operator=(const FirstRanks&) = delete;
  MPI_Comm comm() const { return m_comm; }
  bool member() const { return m_comm != MPI_COMM_NULL; }
  /// The status the members returned, the same on every world rank: -1 where the members'
  /// statuses differ (a non-member's `status` is ignored). Collective over MPI_COMM_WORLD.
  int agreed_status(int status) const {
    int lo = status, hi = status;
    const int big = member() ? status : 1 << 20, small = member() ? status : -1;
    MPI_Allreduce(&big, &lo, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(&small, &hi, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return lo == hi ? hi : -1;
  }

 private:
  MPI_Comm m_comm = MPI_COMM_NULL;
};

/// Sub-communicator sizes to compare: 1, 2, 3, 4 as far as the world allows.
inline std::vector<int> sizes_up_to_world() {
  std::vector<int> s;
  for (int n = 1; n <= std::min(4, world_size()); ++n) s.push_back(n);
  return s;
}

struct Box {
  std::array<std::int64_t, 3> offset{}, dims{};
};

/// Rank `rank` of `size` ranks' box of a global grid: ranks laid out procs[0] x procs[1] x
/// procs[2] (i fastest), each axis split as evenly as integers allow.
inline Box block_of(const std::array<std::int64_t, 3>& global, const std::array<int, 3>& procs, int rank) {
  Box b;
  int c[3] = {rank % procs[0], (rank / procs[0]) % procs[1], rank / (procs[0] * procs[1])};
  for (int a = 0; a < 3; ++a) {
    const std::int64_t base = global[a] / procs[a], extra = global[a] % procs[a];
    b.dims[a] = base + (c[a] < extra ? 1 : 0);
    b.offset[a] = c[a] * base + std::min<std::int64_t>(c[a], extra);
  }
  return b;
}

/// A layout of a local array with one ghost layer per side.
enum class Layout {
  COrder,         ///< i fastest, dense
  FortranPadded,  ///< k fastest, i slowest, each (j,k) plane padded by 3 elements
  MirroredJ,      ///< i fastest, j axis stored backwards (negative stride)
  StructMember,   ///< the value is one member of a 24-byte struct per vertex
};

/// A rank's local array in the given layout and dtype, ghosts filled with a poison value.
class LocalArray {
 public:
  LocalArray(const Box& box, tessera::DType dtype, Layout layout,
             const std::function<double(std::int64_t, std::int64_t, std::int64_t)>& value)
      : m_dtype(dtype) {
    const std::int64_t e = static_cast<std::int64_t>(tessera::dtype_size(dtype));
    for (int a = 0; a < 3; ++a) m_full[a] = box.dims[a] + 2;
    const std::int64_t nx = m_full[0], ny = m_full[1], nz = m_full[2];
    std::int64_t stride[3] = {e, e * nx, e * nx * ny}, start = 0, bytes = e * nx * ny * nz;
    switch (layout) {
      case Layout::COrder: break;
      case Layout::FortranPadded:
        stride[2] = e;
        stride[1] = e * nz;
        stride[0] = e * (nz * ny + 3);
        bytes = stride[0] * nx;
        break;
      case Layout::MirroredJ:
        stride[1] = -e * nx;
        start = e * nx * (ny - 1);
        break;
      case Layout::StructMember:
        stride[0] = 24;
        stride[1] = 24 * nx;
        stride[2] = 24 * nx * ny;
        start = 8;
        bytes = 24 * nx * ny * nz;
        break;
    }
    m_bytes.assign(static_cast<std::size_t>(bytes), 0xA5);
    for (int a = 0; a < 3; ++a) m_strides[a] = stride[a];
    m_base = m_bytes.data() + start;
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i) {
          const bool ghost = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
          const double v =
              ghost ? poison(dtype) : value(box.offset[0] + i - 1, box.offset[1] + j - 1, box.offset[2] + k - 1);
          store(m_base + i * stride[0] + j * stride[1] + k * stride[2], dtype, v);
        }
  }

  tessera::FieldView view() const {
    const std::int64_t one[3] = {1, 1, 1};
    return tessera::FieldView::with_ghosts(m_base, m_dtype, m_full, m_strides, one, one);
  }

  static double poison(tessera::DType t) {
    return t == tessera::DType::Float32 || t == tessera::DType::Float64 ? std::nan("") : 77.0;
  }
  static void store(unsigned char* p, tessera::DType t, double v) {
    switch (t) {
      case tessera::DType::UInt8: {
        const auto x = static_cast<std::uint8_t>(v);
        std::memcpy(p, &x, 1);
        break;
      }
      case tessera::DType::Int16: {
        const auto x = static_cast<std::int16_t>(v);
        std::memcpy(p, &x, 2);
        break;
      }
      case tessera::DType::UInt16: {
        const auto x = static_cast<std::uint16_t>(v);
        std::memcpy(p, &x, 2);
        break;
      }
      case tessera::DType::Float32: {
        const auto x = static_cast<float>(v);
        std::memcpy(p, &x, 4);
        break;
      }
      case tessera::DType::Float64: std::memcpy(p, &v, 8); break;
    }
  }

 private:
  tessera::DType m_dtype;
  std::vector<unsigned char> m_bytes;
  unsigned char* m_base = nullptr;
  std::int64_t m_full[3] = {}, m_strides[3] = {};
};

/// The whole field in C order (i fastest), in `dtype`, as the replica must hold it.
inline std::vector<unsigned char> global_bytes(
    const std::array<std::int64_t, 3>& g, tessera::DType dtype,
    const std::function<double(std::int64_t, std::int64_t, std::int64_t)>& value) {
  const std::size_t e = tessera::dtype_size(dtype);
  std::vector<unsigned char> out(static_cast<std::size_t>(g[0] * g[1] * g[2]) * e);
  std::size_t n = 0;
  for (std::int64_t k = 0; k < g[2]; ++k)
    for (std::int64_t j = 0; j < g[1]; ++j)
      for (std::int64_t i = 0; i < g[0]; ++i, ++n) LocalArray::store(out.data() + n * e, dtype, value(i, j, k));
  return out;
}

/// A smooth field of two blobs on [0, 250] (integer-valued, so exact in every dtype).
inline std::function<double(std::int64_t, std::int64_t, std::int64_t)> blobs(const std::array<std::int64_t, 3>& g) {
  return [g](std::int64_t i, std::int64_t j, std::int64_t k) {
    const double x = static_cast<double>(i) / (g[0] - 1), y = static_cast<double>(j) / (g[1] - 1),
                 z = static_cast<double>(k) / (g[2] - 1);
    const auto blob = [](double dx, double dy, double dz, double r) {
      return std::exp(-(dx * dx + dy * dy + dz * dz) / (r * r));
    };
    const double v = blob(x - 0.35, y - 0.4, z - 0.5, 0.25) + 0.8 * blob(x - 0.7, y - 0.6, z - 0.45, 0.18);
    return std::round(250.0 * std::min(1.0, v));
  };
}

}  // namespace tessera_mpi_test
