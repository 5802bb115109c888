#pragma once
/// Test input for tessera_execute_mesh_domains: a sheared, bent box of hexahedral cells (a
/// curvilinear grid of nx x ny x nz vertices over [-0.5, 0.5]^3, warped smoothly) cut along k
/// into blocks of cells. Each block owns its arrays (coordinates of its vertices, the vertex
/// field, one cell field) and can be published as a curvilinear domain (dims) or as an
/// unstructured list of hexahedra (int32 connectivity in VTK order), or each hex cut into six
/// tetrahedra. The same cells and values in every form.
#include <tessera/tessera.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace tessera_test {

class MeshBlock {
 public:
  /// Cells k0 .. k1-1 of the grid of n[0] x n[1] x n[2] vertices.
  MeshBlock(const std::int64_t n[3], std::int64_t k0, std::int64_t k1) {
    for (int a = 0; a < 3; ++a) m_dims[a] = n[a];
    m_dims[2] = k1 - k0 + 1;
    for (std::int64_t k = k0; k <= k1; ++k)
      for (std::int64_t j = 0; j < n[1]; ++j)
        for (std::int64_t i = 0; i < n[0]; ++i) {
          const double u = double(i) / double(n[0] - 1) - 0.5, v = double(j) / double(n[1] - 1) - 0.5,
                       w = double(k) / double(n[2] - 1) - 0.5;
          x.push_back(u + 0.15 * v * v);
          y.push_back(v + 0.1 * std::sin(2.0 * w));
          z.push_back(w + 0.05 * u);
          const double r2 = (u - 0.1) * (u - 0.1) + v * v + (w + 0.1) * (w + 0.1);
          vertex_values.push_back(std::exp(-r2 / 0.06));
        }
    const std::int64_t cx = n[0] - 1, cy = n[1] - 1, cz = k1 - k0;
    for (std::int64_t k = 0; k < cz; ++k)
      for (std::int64_t j = 0; j < cy; ++j)
        for (std::int64_t i = 0; i < cx; ++i) {
          const auto id = [&](std::int64_t a, std::int64_t b, std::int64_t c) {
            return static_cast<std::int32_t>((c * n[1] + b) * n[0] + a);
          };
          const std::int32_t h[8] = {
              id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
              id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
          hexes.insert(hexes.end(), h, h + 8);
          // Six tetrahedra around the diagonal 0-6, each positively oriented
          static const int kTets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                          {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
          for (const auto& t : kTets)
            for (int q = 0; q < 4; ++q) tets.push_back(h[t[q]]);
          cell_values.push_back(static_cast<double>((i + 2 * j + 3 * (k + k0)) % 7));
        }
  }

  std::vector<double> x, y, z, vertex_values, cell_values;
  std::vector<std::int32_t> hexes, tets;

  enum class Form { Curvilinear, Hexes, Tets };

  /// The domain's descriptor (pointing into this object): `field` "f" per vertex, or with
  /// `cell_data` "f" per cell (not for tets).
  tessera_mesh_domain domain(Form form, bool cell_data = false) {
    m_fields[0] = array("f", cell_data ? cell_values : vertex_values);
    tessera_mesh_domain d{};
    d.association = cell_data ? TESSERA_CELL : TESSERA_VERTEX;
    d.coords = {x.data(), y.data(), z.data(), TESSERA_FLOAT64, 8, static_cast<std::int64_t>(x.size())};
    if (form == Form::Curvilinear) {
      for (int a = 0; a < 3; ++a) d.dims[a] = m_dims[a];
    } else {
      const bool hex = form == Form::Hexes;
      d.shape = hex ? TESSERA_HEX : TESSERA_TET;
      d.connectivity = hex ? hexes.data() : tets.data();
      d.index_dtype = TESSERA_INT32;
      d.ncells = static_cast<std::int64_t>((hex ? hexes.size() : tets.size()) / (hex ? 8 : 4));
    }
    d.fields = m_fields;
    d.nfields = 1;
    return d;
  }

 private:
  static tessera_field array(const char* name, const std::vector<double>& v) {
    tessera_field f{};
    f.name = name;
    f.data = v.data();
    f.dtype = TESSERA_FLOAT64;
    f.dims[0] = static_cast<std::int64_t>(v.size());
    f.dims[1] = f.dims[2] = 1;
    f.byte_strides[0] = 8;
    f.byte_strides[1] = f.byte_strides[2] = 8 * f.dims[0];
    return f;
  }
  std::int64_t m_dims[3];
  tessera_field m_fields[1];
};

}  // namespace tessera_test
