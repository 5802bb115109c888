// tessera-heat --amr: domains of every level (amr_publish.h).
#include "amr_publish.h"

namespace heat {

void append_amr_domains(const std::vector<AmrPatch>& patches, const tessera_field& like,
                        std::vector<tessera_field>& fields, std::vector<tessera_domain>& domains) {
  fields.clear();
  fields.reserve(patches.size());
  for (const AmrPatch& p : patches) {
    tessera_field f = like;
    f.data = p.values.data();
    f.dtype = TESSERA_FLOAT64;
    for (int a = 0; a < 3; ++a) {
      f.dims[a] = p.dims[a];
      f.ghosts_lo[a] = 0;
      f.ghosts_hi[a] = 0;
    }
    f.byte_strides[0] = sizeof(double);
    f.byte_strides[1] = static_cast<std::int64_t>(sizeof(double)) * p.dims[0];
    f.byte_strides[2] = static_cast<std::int64_t>(sizeof(double)) * p.dims[0] * p.dims[1];
    fields.push_back(f);
  }
  for (std::size_t n = 0; n < patches.size(); ++n) {
    tessera_domain d{};
    d.level = patches[n].level;
    for (int a = 0; a < 3; ++a) d.offset[a] = patches[n].offset[a];
    d.fields = &fields[n];
    d.nfields = 1;
    domains.push_back(d);
  }
}

}  // namespace heat
