// A render over curvilinear and unstructured domains (mesh_pass.h).
#include "pass/mesh_pass.h"

#include "data/mesh_binding.h"
#include "data/mesh_exchange.h"
#include "data/mesh_plan.h"
#include "data/mesh_staging.h"
#include "pass/bind_phase.h"
#include "pass/device_phase.h"
#include "pass/pass_report.h"
#include "pass/prepare_phase.h"
#include "pass/render_phase.h"
#include "pass/write_phase.h"

#include <tessera/brick_cache.h>
#include <tessera/config/device_choice.h>
#include <tessera/config/render_memory.h>
#include <tessera/cuda_render.h>
#include <tessera/render.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

namespace tessera::insitu {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Element e of a strided array as double.
double at(const void* base, DType t, std::int64_t stride, std::int64_t e) {
  return detail::load_as_double(t, static_cast<const unsigned char*>(base) + e * stride);
}

/// Whether b.local's geometry, its arrays device memory, hashes on the device as the kept
/// layout's (keep.detected; b.geometry).
bool same_on_device(const PassContext& pass, MeshBinding& b) {
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  b.geometry = cuda_mesh_geometry_hash(b.local, pass.call.cuda_stream);
  b.hashed = true;
  keep.detected = b.geometry == keep.geometry;
  return keep.detected;
}

/// The memory limit a rank's staged copies of device arrays fit in (memory_limit_mb shared by
/// the node's ranks).
config::MemoryLimit staging_limit(const PassContext& pass) {
  return config::memory_limit(pass.cfg.global, std::max(1, pass.ctx.ranks_on_node()));
}

/// Whether b.local is read where it is, on the device, with nothing copied to the host: one
/// rank, every array device memory, the GPU chosen, and the geometry of a kept layout that
/// fits it: `promised` (promised unchanged by tessera_mesh_unchanged, or this call's), or
/// found the same by its hash, computed on the device (keep.detected; b.geometry). The pass
/// then checks its indices and measures its values on the device, and prepare summarises
/// them there (Mesh::device).
bool resident_on_device(const PassContext& pass, MeshBinding& b, const MeshMemory& where, bool promised) {
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  if (pass.ctx.size() != 1 || !keep.layout || !mesh_layout_fits(*keep.layout, b.local) || !where.all_device(b.local) ||
      config::resolve_device(pass.cfg.global, true, pass.ctx.rank_on_node()).device != Device::Cuda)
    return false;
  if (promised) return true;
  if (!keep.geometry_known) return false;
  return same_on_device(pass, b);
}

/// Whether, on several ranks, b.local's geometry may stay in device memory (only its values
/// and ghost masks staged): every array device memory, and this rank holds the geometry of
/// the last full exchange (keep.parts) by the promise or by its hash, computed on the device
/// (keep.detected; b.geometry). The render then reads the geometry from that exchange if
/// every rank agrees (exchange_values_only), else the rest is staged (stage_geometry).
bool geometry_stays_on_device(const PassContext& pass, MeshBinding& b, const MeshMemory& where, bool promised) {
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  if (pass.ctx.size() == 1 || !keep.layout || keep.parts.empty() || !where.all_device(b.local)) return false;
  if (promised) return true;
  if (!keep.geometry_known || keep.decided) return false;
  return same_on_device(pass, b);
}

/// Whether the geometry of this call's mesh is promised to be the kept layout's (promised
/// unchanged by tessera_mesh_unchanged, or this call's first render's, whose layout is kept).
bool promised_unchanged(const MeshLayoutKeep& keep) { return keep.layout != nullptr && (keep.carried || keep.decided); }

/// The check of b.local: on the device when resident; its indices (and finite vertices) only
/// when its geometry is promised or found to be the kept layout's, whose shapes were checked
/// when it was built; not at all when found by its hash to be the geometry of the last check,
/// in the same arrays (that receipt carried to the new values: keep.local_checked); else
/// everything (check_mesh). b.checked: the receipt.
void check_local(const PassContext& pass, MeshBinding& b, bool promised) {
  // (geometry on the device: not read here; it is staged and checked by prepare if the ranks
  // exchange the geometry)
  if (b.local.domains.empty() || b.geometry_on_device) return;
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  if (b.resident) {
    b.checked = cuda_check_mesh_indices(b.local, pass.call.cuda_stream);  // on the device
    return;
  }
  if (b.hashed && keep.local_checked_geometry == b.geometry) {  // (the hash probed every array)
    MeshChecked carried = keep.local_checked.with_new_values(b.local);
    if (carried.covers(b.local, false) && (promised || keep.detected || carried.covers(b.local, true))) {
      b.checked = std::move(carried);
      return;
    }
  }
  if (promised || keep.detected) b.checked = check_mesh_indices(b.local);
  else b.checked = check_mesh(b.local);
  if (b.hashed) {
    keep.local_checked = b.checked;
    keep.local_checked_geometry = b.geometry;
  }
}

/// Of the device arrays `where` names, all but the geometry's (x, y, z, connectivity).
MeshMemory stage_only_values(MeshMemory where) {
  for (std::array<char, kMeshArraySlots>& d : where.device)
    for (const MeshArraySlot s : {MeshArraySlot::X, MeshArraySlot::Y, MeshArraySlot::Z, MeshArraySlot::Connectivity})
      d[static_cast<std::size_t>(s)] = 0;
  return where;
}

/// This rank's mesh bound, its device arrays staged to the host (mesh_staging.h) and checked,
/// or left where they are (resident_on_device, or the geometry alone:
/// geometry_stays_on_device); the ranks agree on the field's dtype and association.
std::optional<MeshBinding> bind_mesh(PhaseGate& gate, const PassContext& pass) {
  const Publication& pub = pass.call.pub;
  // A geometry whose layout is kept (promised unchanged by tessera_mesh_unchanged, found the
  // same by its hash below, or built by this call's first render over the same domains) is
  // checked as prepare checks it (check_mesh_indices: indices and finite vertices, not the
  // shapes that the layout's build checked); if the ranks then do not agree on reusing it,
  // prepare checks the whole mesh's shapes before building a layout (the receipt, b.checked,
  // covers only the indices)
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  const bool promised = promised_unchanged(keep);
  MeshBinding b;
  MeshMemory where;
  if (!gate.run(TESSERA_ERROR_DATA, [&] {
        if (pub.refusal) throw std::invalid_argument(pub.refusal);
        if (!pass.spec.magnitude.empty())
          throw std::invalid_argument("field: {magnitude: [...]} on curvilinear or unstructured domains is not "
                                      "supported yet (publish the magnitude as a field)");
        if (pass.spec.output.cinema)
          throw std::invalid_argument("output.cinema with curvilinear or unstructured domains is not supported yet");
        b = bind_mesh_domains(pub.mesh_domains, pub.ndomains, pass.spec.field, pass.spec.name);
        if (b.local.domains.empty()) return;
        check_mesh_descriptors(b.local);
        where = mesh_memory(b.local);
        b.gpu_readable = where.gpu_readable;
      }))
    return std::nullopt;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        if (!where.on_device()) return;
        if (resident_on_device(pass, b, where, promised)) {
          b.resident = b.local.device = true;
          return;
        }
        const config::MemoryLimit limit = staging_limit(pass);
        b.geometry_on_device = geometry_stays_on_device(pass, b, where, promised);
        stage_mesh_to_host(b.local, b.geometry_on_device ? stage_only_values(where) : where, b.staging,
                           pass.call.cuda_stream, limit.bytes, limit.text);
      }))
    return std::nullopt;
  // The first render of a call over host arrays hashes the geometry (unless the device did):
  // the same as the kept layout's, it is reused without the promise (one pass over the
  // geometry instead of the shapes' check and the layout's sort). Under the promise it is not
  // needed unless the layout is built again (its shapes changed): hashed then, after prepare
  if (!gate.run(TESSERA_ERROR_DATA, [&] {
        if (b.local.domains.empty() || b.resident || b.geometry_on_device || keep.decided || promised || b.hashed)
          return;
        b.geometry = mesh_geometry_hash(b.local);  // its arrays readable first (check_mesh_arrays)
        b.hashed = true;
        // (this rank's domains: the hash covers their counts, dims and shapes; the layout is
        // of every rank's, and prepare still checks that it fits the gathered mesh)
        keep.detected = !promised && keep.layout && keep.geometry_known && keep.geometry == b.geometry;
      }))
    return std::nullopt;
  // One rank: checked now. Several: once the ranks know whether the geometry is exchanged
  // (run_mesh; not when only the values move: the geometry read is then the kept exchange's)
  if (pass.ctx.size() == 1 && !gate.run(TESSERA_ERROR_DATA, [&] { check_local(pass, b, promised); }))
    return std::nullopt;
  if (!gate.run(TESSERA_ERROR_DATA, [&] {
        constexpr int kNone = std::numeric_limits<int>::max();
        const bool has = !b.local.domains.empty();
        const int key = static_cast<int>(b.dtype) * 2 + (b.association == Association::Cell ? 1 : 0);
        const int lo = pass.ctx.min(has ? key : kNone);
        const int hi = -pass.ctx.min(has ? -key : kNone);
        if (lo == kNone)
          throw std::invalid_argument("no rank passed a domain (ndomains = 0 everywhere): the domains make the mesh");
        if (lo != hi)
          throw std::invalid_argument("ranks publish field '" + b.field + "' as " +
                                      dtype_name(static_cast<DType>(lo / 2)) + (lo % 2 ? " cell" : " vertex") +
                                      " data and as " + dtype_name(static_cast<DType>(hi / 2)) +
                                      (hi % 2 ? " cell" : " vertex") + " data");
        b.dtype = static_cast<DType>(lo / 2);
        b.association = lo % 2 ? Association::Cell : Association::Vertex;
      }))
    return std::nullopt;
  return b;
}

/// Several ranks: whether only the values move this render (every rank holds the geometry of
/// the same last full exchange: promised, found by its hash, or this call's). Collective.
bool exchange_values_only(const PassContext& pass) {
  const MeshLayoutKeep& keep = pass.call.mesh_layout;
  const bool holds = keep.layout && !keep.parts.empty() && (keep.same_geometry() || keep.decided);
  const auto tag = static_cast<double>(holds ? keep.parts_call : 0);
  const std::pair<double, double> tags = pass.ctx.range(tag, tag);  // the same exchange on every rank
  return pass.ctx.agree(holds) && tags.first == tags.second;
}

/// The rest of b.local's device arrays (its geometry, left there by bind_mesh) staged too,
/// within what the memory limit leaves beside the values' copies, and hashed as bind_mesh
/// hashes a staged mesh (so that a layout built over it is found again without the promise).
void stage_geometry(const PassContext& pass, MeshBinding& b) {
  const config::MemoryLimit limit = staging_limit(pass);
  const std::uint64_t left = limit.bytes > b.staging.bytes ? limit.bytes - b.staging.bytes : 0;
  stage_mesh_to_host(b.local, mesh_memory(b.local), b.staging, pass.call.cuda_stream, left, limit.text);
  b.geometry_on_device = false;
  if (!b.hashed && !pass.call.mesh_layout.decided) {
    b.geometry = mesh_geometry_hash(b.local);
    b.hashed = true;
  }
}

/// A geometry that bind_mesh did not hash (it was promised unchanged), hashed once a layout
/// has been built over it after all (the promise broken in its shapes, or not made on every
/// rank), so that the next call finds it without the promise: host arrays (the simulation's,
/// or staged) only.
void hash_late(MeshBinding& b) {
  if (b.hashed || b.resident || b.geometry_on_device || b.local.domains.empty()) return;
  b.geometry = mesh_geometry_hash(b.local);
  b.hashed = true;
}

/// One rank: whether this render reuses the kept layout (promised, found by the hash, or this
/// call's), so that the mesh's bounds are the kept ones: those of the geometry the layout draws.
bool kept_bounds(const PassContext& pass, const MeshBinding& b) {
  const MeshLayoutKeep& keep = pass.call.mesh_layout;
  return pass.ctx.size() == 1 && keep.layout && (keep.same_geometry() || keep.decided) &&
         mesh_layout_fits(*keep.layout, b.local);
}

/// The mesh's bounds over every rank's vertices, and every rank's cells.
struct Extent {
  Bounds bounds;
  std::uint64_t cells = 0;         ///< over every rank
  std::uint64_t others_bytes = 0;  ///< the packed bytes of the other ranks' domains
};

/// `values_only`: the geometry's bounds are the kept ones (no coordinate read): every rank
/// holds the last full exchange's geometry, or the one rank's reuses the kept layout
/// (kept_bounds).
Extent extent_of(const PassContext& pass, const MeshBinding& b, bool values_only) {
  const Bounds& kept = pass.call.mesh_layout.bounds;
  if (b.resident) {  // one rank, the kept layout's geometry: its bounds
    Extent e;
    e.bounds = kept;
    for (const MeshDomain& d : b.local.domains) e.cells += static_cast<std::uint64_t>(d.cell_count());
    return e;
  }
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  std::uint64_t cells = 0;
  for (const MeshDomain& d : b.local.domains) {
    const void* xyz[3] = {d.coords.x, d.coords.y, d.coords.z};
    for (int a = 0; a < 3 && !values_only; ++a)
      for (std::int64_t v = 0; v < d.coords.count; ++v) {
        const double x = at(xyz[a], d.coords.dtype, d.coords.byte_stride, v);
        lo[a] = std::min(lo[a], x);
        hi[a] = std::max(hi[a], x);
      }
    cells += static_cast<std::uint64_t>(d.cell_count());
  }
  if (values_only)
    for (int a = 0; a < 3; ++a) lo[a] = kept.lo[a], hi[a] = kept.hi[a];
  Extent e;
  for (int a = 0; a < 3; ++a) {
    const auto [l, h] = pass.ctx.range(lo[a], hi[a]);
    e.bounds.lo[a] = l;
    e.bounds.hi[a] = h;
  }
  const auto n = static_cast<std::size_t>(pass.ctx.size());
  const std::uint64_t mine[2] = {cells, pass.ctx.size() > 1 ? packed_mesh_bytes(b.local) : 0};
  std::vector<std::uint64_t> all(2 * n);
  pass.ctx.allgather(mine, sizeof mine, all.data());
  for (std::size_t r = 0; r < n; ++r) {
    e.cells += all[2 * r];
    if (static_cast<int>(r) != pass.ctx.rank()) e.others_bytes += all[2 * r + 1];
  }
  return e;
}

/// The finite min / max of the field's values over every rank (ghost cells' values left out).
std::pair<double, double> value_range(const PassContext& pass, const MeshBinding& b) {
  if (b.resident) {  // one rank; measured on the device by its check
    const MeshValueTotals* v = b.checked.values();
    return v ? std::pair{v->real_lo, v->real_hi} : cuda_mesh_value_range(b.local, pass.call.cuda_stream);
  }
  double lo = kInf, hi = -kInf;
  for (const MeshDomain& d : b.local.domains)
    for (std::int64_t e = 0; e < d.field.count; ++e) {
      if (d.field.association == Association::Cell && d.ghosts.is_ghost(e)) continue;
      const double v = at(d.field.data, d.field.dtype, d.field.byte_stride, e);
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  return pass.ctx.range(lo, hi);
}

/// Several ranks over the kept layout, the whole mesh's indices checked: each rank summarises
/// a share of the mesh's values and the ranks combine the parts (reduce_parts: the same
/// summary bit for bit) into `shared`, instead of each summarising all of it. Not when the
/// parts would move more bytes than the values' exchange (a fine macrocell grid). Collective;
/// false when a rank failed (the outcome set).
bool share_summary(const PassContext& pass, PhaseGate& gate, const Mesh& whole, const MeshChecked& whole_checked,
                   const SceneDesc& scene, std::shared_ptr<const FieldSummary>& shared) {
  const MeshLayoutKeep& keep = pass.call.mesh_layout;
  bool mine = false;
  FieldSummary::Parts parts;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        std::uint64_t cells = 0;
        for (const MeshDomain& d : whole.domains) cells += static_cast<std::uint64_t>(d.cell_count());
        mine = keep.layout && mesh_layout_fits(*keep.layout, whole) && whole_checked.covers(whole, false) &&
               mesh_summary_cells(*keep.layout, scene) * 17 <= cells * 8 / 2;
        if (mine)
          parts = mesh_summary_parts(whole, scene, keep.layout, whole_checked, pass.ctx.rank(), pass.ctx.size());
      }))
    return false;
  return gate.run(TESSERA_ERROR_RENDER, [&] {
    // (every rank's parts of the same size before the reductions: the same mesh, layout and
    // config give the same grid; anything else keeps every rank on its own summary)
    const auto size = static_cast<double>(mine ? parts.lo.size() : 0);
    const std::pair<double, double> sizes = pass.ctx.range(size, size);
    if (!pass.ctx.agree(mine) || sizes.first != sizes.second) return;
    pass.ctx.reduce_parts(parts);
    shared = mesh_summary_of_parts(std::move(parts), whole, scene, keep.layout);
  });
}

}  // namespace

void run_mesh(const PassContext& pass, PhaseGate& gate, PassOutcome& out, bool check_when, bool quiet) {
  std::optional<MeshBinding> bound = bind_mesh(gate, pass);
  if (!bound) return;
  // Several ranks: whether only the values move (every rank holds the geometry of the last
  // full exchange); if not, a rank whose geometry stayed on the device stages it now, and each
  // rank checks its domains (bind_mesh's check on one rank)
  bool values_only = false;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        if (pass.ctx.size() == 1) return;
        values_only = exchange_values_only(pass);
        if (!values_only && bound->geometry_on_device) stage_geometry(pass, *bound);
      }))
    return;
  if (pass.ctx.size() > 1 && !values_only &&
      !gate.run(TESSERA_ERROR_DATA, [&] { check_local(pass, *bound, promised_unchanged(pass.call.mesh_layout)); }))
    return;
  Extent extent;
  if (!gate.run(TESSERA_ERROR_RENDER,
                [&] { extent = extent_of(pass, *bound, values_only || kept_bounds(pass, *bound)); }))
    return;
  std::pair<double, double> range{0.0, 0.0};
  if (check_when || pass.spec.transfer_function.range.automatic) {
    std::pair<double, double> r{kInf, -kInf};
    if (!gate.run(TESSERA_ERROR_RENDER, [&] { r = value_range(pass, *bound); })) return;
    if (check_when && !pass.render.trigger.fires_on_max(r.second)) {
      out.fired = false;
      return;
    }
    if (r.first <= r.second) range = r;
  }
  if (pass.spp == 0) {
    out = skipped(pass, std::move(out));
    return;
  }
  FieldPlan plan;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        plan = plan_mesh(pass.cfg, pass.spec, pass.ctx.size(), pass.ctx.ranks_on_node(), pass.root(), extent.cells,
                         extent.others_bytes);
      }))
    return;
  // Several ranks: every rank's domains here (a copy of the others'). When every rank checked
  // its own domains' shapes (check_local: none promised them unchanged), only the copies'
  // indices are checked again (check_mesh_copy: no read outside them, whatever came); else
  // prepare checks as it would. One rank: in place, with bind_mesh's receipt
  // When every rank holds the geometry of the last full exchange (promised, found by its hash,
  // or this call's), only the values move: the geometry is read from that exchange's bytes,
  // whose shapes were checked when the structure was built over them and whose indices were
  // checked once since (keep.parts_checked, carried to the new values)
  MeshLayoutKeep& keep = pass.call.mesh_layout;
  std::vector<std::string> received;
  Mesh whole;
  MeshChecked whole_checked;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        if (pass.ctx.size() == 1) {
          whole = bound->local;
          whole_checked = bound->checked;
          return;
        }
        const bool shapes_checked =
            pass.ctx.agree(bound->local.domains.empty() || bound->checked.covers(bound->local, true));
        if (values_only) {
          received = pass.ctx.allgather_bytes(pack_values(bound->local), plan.limit);
          whole = unpack_with_values(keep.parts, received);
          // The kept bytes' receipt (checked once after the exchange): only the values are new
          whole_checked = keep.parts_checked.with_new_values(whole);
          if (!whole_checked.covers(whole, false)) keep.parts_checked = whole_checked = check_mesh_copy(whole);
          return;
        }
        received = pass.ctx.allgather_bytes(pack_mesh(bound->local), plan.limit);
        whole = unpack_meshes(received);
        if (shapes_checked) whole_checked = check_mesh_copy(whole);
      }))
    return;
  std::uint64_t exchanged = 0;  // bytes received from the ranks (this rank's own included)
  for (const std::string& part : received) exchanged += part.size();
  const std::optional<config::DeviceSelection> device = mesh_device_phase(gate, pass, bound->gpu_readable);
  if (!device) return;
  out.result.device = config::device_text(*device);
  out.result.stats.bytes_to_host += bound->staging.bytes;
  BoundField field;  // what the scene phase reads of a field: its bounds
  field.binding.global_bounds = extent.bounds;
  field.name = bound->field;
  std::optional<SceneSetup> setup = scene_phase(gate, pass, field, range);
  if (!setup) return;
  set_device_options(pass, *device, setup->scene.options);
  // The layout of the last call (every rank promised the same geometry) or of this call's
  // first render over the mesh
  const bool first = !keep.decided;
  if (first) {
    if (!pass.ctx.agree(keep.same_geometry() && keep.layout != nullptr)) {
      keep.layout.reset();
      if (!values_only) {  // (values only: every rank agreed it holds them; `whole` views them)
        keep.parts.clear();
        keep.parts_checked = {};
      }
    }
    keep.decided = true;
  }
  std::shared_ptr<const FieldSummary> shared;
  const auto shared_t0 = PassClock::now();  // (part of the prepare: counted in its seconds)
  if (pass.ctx.size() > 1 && !share_summary(pass, gate, whole, whole_checked, setup->scene, shared)) return;
  out.result.prepare_seconds += std::chrono::duration<double>(PassClock::now() - shared_t0).count();
  PreparedScene prepared;
  if (!gate.run(TESSERA_ERROR_RENDER, [&] {
        const auto t0 = PassClock::now();
        try {
          prepared = shared ? prepare(whole, setup->scene, keep.layout, whole_checked, shared)
                            : prepare(whole, setup->scene, keep.layout, whole_checked);  // not checked again
          keep.layout = prepared.mesh_layout();
          keep.bounds = extent.bounds;
          keep.holds_layout();
          if (pass.ctx.size() > 1 && !values_only) {  // the geometry the layout is of, for the next renders
            keep.parts = std::move(received);         // moves the buffers: `whole` still views them
            keep.parts_call = keep.calls;
            keep.parts_checked = whole_checked;  // (empty when prepare checked `whole` itself)
          }
          if (first && !prepared.mesh_layout_reused()) {  // the geometry it was built over
            keep.geometry_known = false;                  // (not the last layout's, if the hash throws)
            hash_late(*bound);
            keep.geometry = bound->geometry;
            keep.geometry_known = bound->hashed;
          }
        } catch (const DeadlineExceeded& e) {
          time_limit_passed(pass, e);
        }
        out.result.prepare_seconds += std::chrono::duration<double>(PassClock::now() - t0).count();
        ++out.result.field_passes;  // the values' ranges: always read
        out.result.mesh_layout_reused = prepared.mesh_layout_reused();
        out.result.mesh_values_only = values_only;
        out.result.mesh_summary_shared = shared != nullptr;
        out.result.mesh_exchange_bytes = exchanged;
      }))
    return;
  std::optional<Image> img = render_phase(gate, pass, prepared, out.result);
  if (!img || !write_phase(gate, pass, setup->scene, std::move(*img), out.result)) return;
  finish(pass, prepared, plan, 0, quiet, out);
}

}  // namespace tessera::insitu
