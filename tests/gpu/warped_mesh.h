#pragma once
// Mesh input for the GPU tests: a smoothly warped box of n^3 vertices over about [0, 1]^3
// carrying the heat field (gpu_test_util.h), cut along k into pieces, each published as one
// domain of a chosen kind: curvilinear (x, y, z interleaved in one float32 array), or an
// unstructured list of hexahedra or of tetrahedra (six per hex, positively oriented) with
// separate float64 coordinate arrays and int32 or int64 connectivity; values per vertex or
// per cell in any dtype the heat field's range fits (float32, float64, int16, uint16), at a
// stride of two elements. Every kind of array a device copy of a mesh relocates.
#include <tessera/byte_span.h>
#include <tessera/mesh.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace gpu_test {

enum class MeshForm { Curvilinear, Hexes, Tets };

class WarpedMeshPiece {
 public:
  /// Cells k0 .. k1-1 (along k) of the box of n^3 vertices.
  WarpedMeshPiece(int n, int k0, int k1, MeshForm form, tessera::DType dtype, bool cell_data, bool index64 = false)
      : m_form(form), m_dtype(dtype), m_cell_data(cell_data), m_index64(index64) {
    m_dims[0] = m_dims[1] = n;
    m_dims[2] = k1 - k0 + 1;
    const double h = 1.0 / (n - 1);
    std::vector<double> vertex_values;
    for (int k = k0; k <= k1; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double u = i * h, v = j * h, w = k * h;
          const double p[3] = {u + 0.06 * std::sin(3.0 * v), v + 0.05 * w * w, w + 0.04 * u};
          if (form == MeshForm::Curvilinear)
            for (const double c : p) m_xyz32.push_back(static_cast<float>(c));
          else m_x.push_back(p[0]), m_y.push_back(p[1]), m_z.push_back(p[2]);
          vertex_values.push_back(heat(u, v, w));
        }
    std::vector<double> cell_values;
    const std::int64_t cx = n - 1, cy = n - 1;
    for (int k = 0; k < k1 - k0; ++k)
      for (int j = 0; j < cy; ++j)
        for (int i = 0; i < cx; ++i) {
          const auto id = [&](std::int64_t a, std::int64_t b, std::int64_t c) { return (c * n + b) * n + a; };
          const std::int64_t hx[8] = {
              id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
              id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
          const double centre = heat((i + 0.5) * h, (j + 0.5) * h, (k0 + k + 0.5) * h);
          if (form == MeshForm::Tets) {
            static const int kTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                            {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
            for (const auto& t : kTets) {
              for (const int q : t) m_conn.push_back(hx[q]);
              cell_values.push_back(centre);
            }
          } else {
            if (form == MeshForm::Hexes) m_conn.insert(m_conn.end(), hx, hx + 8);
            cell_values.push_back(centre);
          }
        }
    m_cells = static_cast<std::int64_t>(cell_values.size());
    for (const std::int64_t c : m_conn) m_conn32.push_back(static_cast<std::int32_t>(c));
    const std::vector<double>& vals = cell_data ? cell_values : vertex_values;
    m_count = static_cast<std::int64_t>(vals.size());
    const std::size_t es = tessera::dtype_size(dtype);
    m_values.assign(2 * es * vals.size(), 0xEE);  // every other element: filler the render must not read
    for (std::size_t e = 0; e < vals.size(); ++e) store(vals[e], m_values.data() + 2 * es * e);
  }

  /// The domain's view of this piece's arrays.
  tessera::MeshDomain domain() const {
    tessera::MeshDomain d;
    if (m_form == MeshForm::Curvilinear) {
      d.coords = {m_xyz32.data(),          m_xyz32.data() + 1, m_xyz32.data() + 2,
                  tessera::DType::Float32, 3 * sizeof(float),  static_cast<std::int64_t>(m_xyz32.size() / 3)};
      for (int a = 0; a < 3; ++a) d.dims[a] = m_dims[a];
    } else {
      d.coords = {m_x.data(),     m_y.data(),
                  m_z.data(),     tessera::DType::Float64,
                  sizeof(double), static_cast<std::int64_t>(m_x.size())};
      d.shape = m_form == MeshForm::Hexes ? tessera::Shape::Hex : tessera::Shape::Tet;
      d.connectivity = m_index64 ? static_cast<const void*>(m_conn.data()) : static_cast<const void*>(m_conn32.data());
      d.index_type = m_index64 ? tessera::IndexType::Int64 : tessera::IndexType::Int32;
      d.ncells = m_cells;
    }
    d.field.data = m_values.data();
    d.field.dtype = m_dtype;
    d.field.byte_stride = static_cast<std::int64_t>(2 * tessera::dtype_size(m_dtype));
    d.field.count = m_count;
    d.field.association = m_cell_data ? tessera::Association::Cell : tessera::Association::Vertex;
    return d;
  }

  /// Overwrites every array the domain points to (coordinates, connectivity, values).
  void scribble() {
    scribble_geometry();
    for (unsigned char& b : m_values) b = 0x7F;
  }
  /// Overwrites the geometry's arrays only (coordinates, connectivity).
  void scribble_geometry() {
    for (float& c : m_xyz32) c = 1.0e30f;
    for (std::vector<double>* c : {&m_x, &m_y, &m_z})
      for (double& v : *c) v = -1.0e300;
    for (std::int64_t& c : m_conn) c = -5;
    for (std::int32_t& c : m_conn32) c = 1 << 30;
  }

 private:
  static double heat(double u, double v, double w) {
    const double x = u - 0.55, y = v - 0.45, z = w - 0.5;
    return 300.0 + 900.0 * std::exp(-(x * x + y * y + z * z) / 0.03) + 80.0 * v;
  }
  void store(double v, unsigned char* p) const {
    switch (m_dtype) {
      case tessera::DType::Float32: {
        const auto t = static_cast<float>(v);
        std::memcpy(p, &t, sizeof t);
        break;
      }
      case tessera::DType::Int16: {
        const auto t = static_cast<std::int16_t>(std::lround(v));
        std::memcpy(p, &t, sizeof t);
        break;
      }
      case tessera::DType::UInt16: {
        const auto t = static_cast<std::uint16_t>(std::lround(v));
        std::memcpy(p, &t, sizeof t);
        break;
      }
      default: std::memcpy(p, &v, sizeof v);
    }
  }

  MeshForm m_form;
  tessera::DType m_dtype;
  bool m_cell_data, m_index64;
  std::int64_t m_dims[3] = {0, 0, 0};
  std::int64_t m_cells = 0, m_count = 0;
  std::vector<float> m_xyz32;
  std::vector<double> m_x, m_y, m_z;
  std::vector<std::int64_t> m_conn;
  std::vector<std::int32_t> m_conn32;
  std::vector<unsigned char> m_values;
};

/// Bytes of a mesh's geometry arrays (x, y, z, connectivity), each domain's overlapping ones
/// (interleaved x, y, z) counted once: what a device render copies of them.
inline std::uint64_t geometry_bytes(const tessera::Mesh& mesh) {
  std::uint64_t total = 0;
  for (const tessera::MeshDomain& d : mesh.domains) {
    std::vector<tessera::AddressSpan> spans;
    for (int s = 0; s < 4; ++s) {
      const tessera::MeshArraySpan a = tessera::mesh_array(d, static_cast<tessera::MeshArraySlot>(s));
      const auto* p = static_cast<const unsigned char*>(a.data);
      if (p) spans.push_back({p, p + a.bytes, s});
    }
    for (const tessera::SpanRun& r : tessera::merge_spans(spans)) total += static_cast<std::uint64_t>(r.hi - r.lo);
  }
  return total;
}

/// A mesh of the given pieces (views of their arrays).
inline tessera::Mesh mesh_of(const std::vector<WarpedMeshPiece>& pieces) {
  tessera::Mesh m;
  for (const WarpedMeshPiece& p : pieces) m.domains.push_back(p.domain());
  return m;
}

}  // namespace gpu_test
