#pragma once
/// Test input for tessera_execute_domains: one global field cut into domains the way a
/// simulation holds them. Each domain has its own float32 array with ghost layers on every
/// side, in a layout of its own (i fastest, or k fastest), and its ghost values are NaN: the
/// renderer never reads ghosts, so a ghost read would change the image (and the NaN count).
/// Values are small integers (exact in float32). The mesh may be vertex or cell data, with
/// uniform or stretched (rectilinear) axes: the harness is the same for all of them.
#include <tessera/tessera.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <vector>

namespace tessera_test {

using Dims = std::array<std::int64_t, 3>;

struct CutBox {
  Dims offset;
  Dims dims;
};

/// Seven uneven boxes tiling `g` (each axis >= 8): a slab along i cut in two along j, a slab
/// cut in two along j, and a slab cut in three along k.
inline std::vector<CutBox> seven_cuts(const Dims& g) {
  const std::int64_t i1 = g[0] / 5, i2 = g[0] * 3 / 5;
  const std::int64_t j1 = g[1] * 3 / 4, j2 = g[1] / 3;
  const std::int64_t k1 = g[2] / 4, k2 = g[2] * 2 / 3;
  return {
      {{0, 0, 0}, {i1, j1, g[2]}},
      {{0, j1, 0}, {i1, g[1] - j1, g[2]}},
      {{i1, 0, 0}, {i2 - i1, j2, g[2]}},
      {{i1, j2, 0}, {i2 - i1, g[1] - j2, g[2]}},
      {{i2, 0, 0}, {g[0] - i2, g[1], k1}},
      {{i2, 0, k1}, {g[0] - i2, g[1], k2 - k1}},
      {{i2, 0, k2}, {g[0] - i2, g[1], g[2] - k2}},
  };
}

/// The global field: integer blobs in [0, 250] over the element index (i, j, k) of g.
inline float global_value(const Dims& g, std::int64_t i, std::int64_t j, std::int64_t k) {
  const double x = static_cast<double>(i) / static_cast<double>(g[0] - 1) - 0.45;
  const double y = static_cast<double>(j) / static_cast<double>(g[1] - 1) - 0.5;
  const double z = static_cast<double>(k) / static_cast<double>(g[2] - 1) - 0.55;
  const double r2 = x * x + 1.3 * y * y + z * z;
  return static_cast<float>(
      std::round(250.0 * std::exp(-r2 / 0.07) + 40.0 * std::exp(-((x - 0.3) * (x - 0.3) + y * y) / 0.02)));
}

/// The mesh of g elements over [-0.5, 0.5]^3 (vertex data: g vertices; cell data: g cells).
inline tessera_mesh unit_mesh(const Dims& g, tessera_association assoc) {
  tessera_mesh m{};
  m.association = assoc;
  m.nlevels = 1;
  for (int a = 0; a < 3; ++a) {
    m.origin[a] = -0.5;
    m.spacing[a] = 1.0 / static_cast<double>(assoc == TESSERA_CELL ? g[a] : g[a] - 1);
    m.global_dims[a] = g[a];
  }
  return m;
}

/// The axes of a test mesh: all uniform, y stretched, or all three stretched.
enum class Axes { Uniform, StretchedY, StretchedAll };

inline const char* axes_name(Axes axes) {
  return axes == Axes::Uniform ? "uniform" : axes == Axes::StretchedY ? "y stretched" : "xyz stretched";
}

/// `count` strictly increasing coordinates over [-0.5, 0.5], bunched at one end: t + s t^2 (1 - t)
/// at t = q / (count - 1), whose slope 1 + s (2t - 3t^2) stays above 0 for s in (-3, 1).
inline std::vector<double> stretched_axis(std::int64_t count, double s) {
  std::vector<double> c(static_cast<std::size_t>(count));
  for (std::size_t q = 0; q < c.size(); ++q) {
    const double t = count > 1 ? static_cast<double>(q) / static_cast<double>(count - 1) : 0.0;
    c[q] = -0.5 + t + s * t * t * (1.0 - t);
  }
  c.back() = 0.5;
  return c;
}

/// unit_mesh() with `axes` stretched over the same box [-0.5, 0.5]^3: the coordinates live
/// here (the mesh points into them), so an object of this class outlives its meshes.
class TestMesh {
 public:
  TestMesh(const Dims& g, tessera_association assoc, Axes axes) : m_mesh(unit_mesh(g, assoc)) {
    static constexpr double kStretch[3] = {0.6, -0.5, 0.8};
    for (int a = 0; a < 3; ++a) {
      if (axes == Axes::Uniform || (axes == Axes::StretchedY && a != 1)) continue;
      m_coords[a] = stretched_axis(g[a] + (assoc == TESSERA_CELL ? 1 : 0), kStretch[a]);
      m_mesh.coords[a] = m_coords[a].data();
    }
  }
  TestMesh(const TestMesh&) = delete;
  TestMesh& operator=(const TestMesh&) = delete;
  const tessera_mesh& mesh() const { return m_mesh; }

 private:
  tessera_mesh m_mesh;
  std::array<std::vector<double>, 3> m_coords;
};

/// Domains as a simulation holds them (addresses stable: the descriptors point into them).
class HeldDomains {
 public:
  /// One domain per box, `ghosts` layers on every side, the layout alternating between i
  /// fastest and k fastest.
  HeldDomains(const Dims& g, const std::vector<CutBox>& boxes, int ghosts = 1) {
    for (std::size_t n = 0; n < boxes.size(); ++n) add(g, boxes[n], ghosts, n % 2 == 1);
  }
  void add(const Dims& g, const CutBox& b, int ghosts, bool k_fastest) {
    Held& h = m_held.emplace_back();
    Dims d;
    for (int a = 0; a < 3; ++a) d[a] = b.dims[a] + 2 * ghosts;
    h.data.assign(static_cast<std::size_t>(d[0] * d[1] * d[2]), std::numeric_limits<float>::quiet_NaN());
    std::int64_t stride[3];
    if (k_fastest) {
      stride[2] = 1, stride[1] = d[2], stride[0] = d[2] * d[1];
    } else {
      stride[0] = 1, stride[1] = d[0], stride[2] = d[0] * d[1];
    }
    for (std::int64_t k = 0; k < b.dims[2]; ++k)
      for (std::int64_t j = 0; j < b.dims[1]; ++j)
        for (std::int64_t i = 0; i < b.dims[0]; ++i)
          h.data[static_cast<std::size_t>((i + ghosts) * stride[0] + (j + ghosts) * stride[1] +
                                          (k + ghosts) * stride[2])] =
              global_value(g, b.offset[0] + i, b.offset[1] + j, b.offset[2] + k);
    h.field.name = "density";
    h.field.data = h.data.data();
    h.field.dtype = TESSERA_FLOAT32;
    for (int a = 0; a < 3; ++a) {
      h.field.dims[a] = d[a];
      h.field.byte_strides[a] = 4 * stride[a];
      h.field.ghosts_lo[a] = h.field.ghosts_hi[a] = ghosts;
      h.domain.offset[a] = b.offset[a];
    }
    h.domain.level = 0;
    h.domain.fields = &h.field;
    h.domain.nfields = 1;
  }
  /// The descriptors of the domains whose index n satisfies n % ranks == rank (all: ranks 1).
  std::vector<tessera_domain> of_rank(int rank, int ranks) const {
    std::vector<tessera_domain> out;
    for (std::size_t n = 0; n < m_held.size(); ++n)
      if (static_cast<int>(n % static_cast<std::size_t>(ranks)) == rank) out.push_back(m_held[n].domain);
    return out;
  }
  tessera_field& field(std::size_t n) { return m_held[n].field; }
  tessera_domain& domain(std::size_t n) { return m_held[n].domain; }
  std::size_t size() const { return m_held.size(); }

 private:
  struct Held {
    std::vector<float> data;
    tessera_field field{};
    tessera_domain domain{};
  };
  std::deque<Held> m_held;
};

}  // namespace tessera_test
