#include "shell_publish.h"

namespace heat {

ShellBlock::ShellBlock(const ShellGeometry& geometry, std::int64_t first_column, std::int64_t owned_columns)
    : m_geometry(geometry),
      m_columns(owned_columns + 1),
      m_coords(shell_block_coordinates(geometry, first_column, owned_columns + 1)) {}

const tessera_mesh_domain& ShellBlock::domain(const ShellSolver& solver, const char* field_name) {
  const std::int64_t count = m_geometry.n_z * m_geometry.n_r * m_columns;
  // The temperature: one value per vertex, contiguous from the first owned column
  m_field = tessera_field{};
  m_field.name = field_name;
  m_field.dtype = TESSERA_FLOAT64;
  m_field.data = solver.data() + solver.column_size();
  m_field.dims[0] = count;
  m_field.dims[1] = 1;
  m_field.dims[2] = 1;
  m_field.byte_strides[0] = sizeof(double);
  m_field.byte_strides[1] = sizeof(double) * count;
  m_field.byte_strides[2] = sizeof(double) * count;
  // The block: z fastest, then r, then the angle (a right-handed logical frame)
  m_domain = tessera_mesh_domain{};
  m_domain.association = TESSERA_VERTEX;
  m_domain.coords.x = m_coords.x.data();
  m_domain.coords.y = m_coords.y.data();
  m_domain.coords.z = m_coords.z.data();
  m_domain.coords.dtype = TESSERA_FLOAT64;
  m_domain.coords.byte_stride = sizeof(double);
  m_domain.coords.count = count;
  m_domain.dims[0] = m_geometry.n_z;
  m_domain.dims[1] = m_geometry.n_r;
  m_domain.dims[2] = m_columns;
  m_domain.shape = TESSERA_HEX;
  m_domain.index_dtype = TESSERA_INT32;
  m_domain.fields = &m_field;
  m_domain.nfields = 1;
  return m_domain;
}

}  // namespace heat
