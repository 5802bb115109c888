// The bind phase of a render (bind_phase.h).
#include "pass/bind_phase.h"

#include "data/domain_binding.h"
#include "data/vector_binding.h"

#include <tessera/config/render_memory.h>

#include <algorithm>

#include <limits>
#include <span>
#include <stdexcept>

namespace tessera::insitu {
namespace {

/// tessera_execute: the grid and its field list; `field_name` the render's field.
void bind_grid(const PassContext& pass, const std::string& field_name, BoundField& f) {
  const Publication& pub = pass.call.pub;
  if (pub.nfields < 0 || (pub.nfields > 0 && !pub.fields))
    throw std::invalid_argument("field list is invalid (fields = " + std::string(pub.fields ? "non-null" : "NULL") +
                                ", nfields = " + std::to_string(pub.nfields) + ")");
  if (!pub.grid) throw std::invalid_argument("grid descriptor is NULL");
  const std::span<const tessera_field> fields(pub.fields, static_cast<std::size_t>(pub.nfields));
  const tessera_field& field = fields[find_field(fields, field_name, pass.spec.name)];
  f.binding = bind_field(field, *pub.grid);
  require_readable(f.binding, field_label(field));
  // Every other published field's descriptors against the grid (descriptors only: no value is
  // read), so that a wrong one is found at the first call that renders, not when drawn
  for (const tessera_field& other : fields)
    if (&other != &field) (void)bind_field(other, *pub.grid);
  if (pass.ctx.size() == 1) require_whole_grid(field, f.binding);
  f.name = field.name;
}

/// tessera_execute_domains: this rank's domains (domain_binding.h), then the ranks agree on
/// the field's dtype and association (a rank without domains learns them, and sees the mesh as
/// the field does; ranks whose dtypes or associations differ, or no domain anywhere, fail
/// alike on every rank with TESSERA_ERROR_DATA).
bool bind_all_domains(PhaseGate& gate, const PassContext& pass, const std::string& field_name, BoundField& f) {
  const Publication& pub = pass.call.pub;
  if (!gate.run(TESSERA_ERROR_DATA, [&] {
        f.binding = bind_domains(pub.mesh, pub.domains, pub.ndomains, field_name, pass.spec.name);
        f.name = field_name;
        if (!f.binding.blocks.empty()) {
          const std::span<const tessera_field> fields(pub.domains[0].fields,
                                                      static_cast<std::size_t>(pub.domains[0].nfields));
          f.name = fields[find_field(fields, field_name, pass.spec.name)].name;
        }
        require_readable(f.binding, "field '" + f.name + "'");
      }))
    return false;
  return gate.run(TESSERA_ERROR_DATA, [&] {
    constexpr int kNone = std::numeric_limits<int>::max();
    const bool has = !f.binding.blocks.empty();
    const int mine = has ? static_cast<int>(f.binding.local.dtype) : kNone;
    const int lo = pass.ctx.min(mine);
    const int hi = -pass.ctx.min(has ? -mine : kNone);  // the largest over the ranks with domains
    if (lo == kNone)
      throw LayoutError("no rank passed a domain (ndomains = 0 everywhere): the domains must cover the mesh");
    if (lo != hi)
      throw LayoutError("ranks publish field '" + f.name + "' with different dtypes (" +
                        dtype_name(static_cast<DType>(lo)) + " and " + dtype_name(static_cast<DType>(hi)) + ")");
    f.binding.local.dtype = static_cast<DType>(lo);
    // The field's association: a rank without domains bound the mesh's own
    const int cells = f.binding.geometry.association == Association::Cell ? 1 : 0;
    const int any_cells = -pass.ctx.min(has ? -cells : 0);
    const int all_cells = pass.ctx.min(has ? cells : 1);
    if (any_cells != all_cells)
      throw LayoutError("ranks publish field '" + f.name + "' with different associations (vertex and cell data)");
    if (!has && cells != all_cells) set_geometry(f.binding, mesh_for(*pub.mesh, all_cells == 1, f.name));
  });
}

/// The field `field_name` by the call's kind (grid or domains).
bool bind_one(PhaseGate& gate, const PassContext& pass, const std::string& field_name, BoundField& f) {
  if (pass.call.pub.domains_call) return bind_all_domains(gate, pass, field_name, f);
  return gate.run(TESSERA_ERROR_DATA, [&] { bind_grid(pass, field_name, f); });
}

/// `field: {magnitude: [a, b, c]}`: each component bound as a field, then combined
/// (vector_binding.h): in place on one rank holding the grid whole, else staged. The bound
/// field's name is the render's field_key(), so that what the adapter keeps for it is apart
/// from what it keeps for the components.
bool bind_magnitude(PhaseGate& gate, const PassContext& pass, BoundField& f) {
  FieldBinding parts[3];
  std::string names[3];
  for (int c = 0; c < 3; ++c) {
    BoundField one;
    if (!bind_one(gate, pass, pass.spec.magnitude[static_cast<std::size_t>(c)], one)) return false;
    parts[c] = std::move(one.binding);
    names[c] = one.name;
  }
  return gate.run(TESSERA_ERROR_DATA, [&] {
    const config::MemoryLimit limit = config::memory_limit(pass.cfg.global, std::max(1, pass.ctx.ranks_on_node()));
    // Components in device memory: staged to the host first (the magnitude is computed there)
    for (FieldBinding& part : parts)
      if (const BlocksMemory where = blocks_memory(part.blocks); where.on_device())
        stage_blocks_to_host(part, where, f.device.staging, pass.call.cuda_stream, limit.bytes, limit.text);
    VectorField v = combine_components(parts, names, pass.ctx.size() == 1, limit.bytes, limit.text);
    f.binding = std::move(v.binding);
    f.magnitude = v.in_place;
    f.staged = std::move(v.staged);
    f.binding.staged_bytes = v.staged_bytes;
    f.name = pass.spec.field_key();
  });
}

}  // namespace

std::optional<BoundField> bind_phase(PhaseGate& gate, const PassContext& pass) {
  BoundField f;
  const Publication& pub = pass.call.pub;
  if (pub.refusal) {
    gate.run(TESSERA_ERROR_DATA, [&] { throw std::invalid_argument(pub.refusal); });
    return std::nullopt;
  }
  if (!pass.spec.magnitude.empty()) {
    if (!bind_magnitude(gate, pass, f)) return std::nullopt;
  } else if (!bind_one(gate, pass, pass.spec.field, f)) {
    return std::nullopt;
  }
  // Refinement levels: every rank's boxes checked as one hierarchy, on every rank alike
  if (f.binding.nlevels > 1 && !gate.run(TESSERA_ERROR_DATA, [&] {
        f.amr = pass.ctx.amr_layout(f.binding.blocks, amr_meta(f.binding, f.binding.local.dtype),
                                    f.binding.geometry.association);
      }))
    return std::nullopt;
  return f;
}

}  // namespace tessera::insitu
