#include "published_blocks.h"

#include "cli_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace heat {

PublishedBlocks::PublishedBlocks(const CartDecomposition& decomp, const Index3& array_dims,
                                 const std::array<double, 3>& spacing, int blocks, bool cell)
    : m_array(array_dims), m_offset(decomp.offset()) {
  const Index3& owned = decomp.owned();
  m_axis = static_cast<int>(std::max_element(owned.begin(), owned.end()) - owned.begin());
  const std::int64_t m = owned[m_axis];
  if (blocks < 1 || blocks > kMaxBlocksPerRank || blocks > m)
    throw std::invalid_argument("--domains-per-rank " + std::to_string(blocks) + ": need 1.." +
                                std::to_string(std::min<std::int64_t>(m, kMaxBlocksPerRank)) +
                                " (this rank owns " + std::to_string(m) + " planes along its longest axis)");
  std::int64_t prev = 0;
  for (int p = 1; p <= blocks; ++p) {
    std::int64_t b = std::llround(static_cast<double>(m) * std::pow(static_cast<double>(p) / blocks, 1.3));
    b = std::min(std::max(b, prev + 1), m - (blocks - p));
    m_cuts.push_back({prev, b});
    prev = b;
  }
  m_mesh.association = cell ? TESSERA_CELL : TESSERA_VERTEX;
  for (int a = 0; a < 3; ++a) {
    m_mesh.origin[a] = cell ? -0.5 * spacing[a] : 0.0;  // cells centred on the vertices
    m_mesh.spacing[a] = spacing[a];
    m_mesh.coords[a] = nullptr;
    m_mesh.global_dims[a] = decomp.global_dims()[a];
  }
  m_mesh.nlevels = 1;
  m_mesh.refinement = nullptr;
  m_fields.resize(m_cuts.size());
  m_domains.resize(m_cuts.size());
}

std::span<const tessera_domain> PublishedBlocks::domains(const double* data) {
  const std::int64_t stride[3] = {static_cast<std::int64_t>(sizeof(double)),
                                  static_cast<std::int64_t>(sizeof(double)) * m_array[0],
                                  static_cast<std::int64_t>(sizeof(double)) * m_array[0] * m_array[1]};
  for (std::size_t d = 0; d < m_cuts.size(); ++d) {
    // Array planes lo .. hi + 1 along the cut axis (owned plane q is array plane q + 1): the
    // block's owned planes and one ghost plane at both ends
    const Cut& c = m_cuts[d];
    tessera_field& f = m_fields[d];
    f.name = "temperature";
    f.dtype = TESSERA_FLOAT64;
    f.data = reinterpret_cast<const unsigned char*>(data) + c.lo * stride[m_axis];
    for (int a = 0; a < 3; ++a) {
      f.dims[a] = a == m_axis ? c.hi - c.lo + 2 : m_array[a];
      f.byte_strides[a] = stride[a];
      f.ghosts_lo[a] = 1;
      f.ghosts_hi[a] = 1;
    }
    tessera_domain& dom = m_domains[d];
    dom.level = 0;
    for (int a = 0; a < 3; ++a) dom.offset[a] = m_offset[a] + (a == m_axis ? c.lo : 0);
    dom.fields = &f;
    dom.nfields = 1;
  }
  return m_domains;
}

}  // namespace heat
