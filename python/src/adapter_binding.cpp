// tessera._tessera.Adapter: tessera.Adapter's C++ half over tessera::insitu::Adapter (the C
// API's own implementation). Open, execute and close run with the GIL released; the fields
// arrive as descriptors of the caller's arrays (tessera/_arrays.py), read in place. Each
// execute returns its own outcome (status, message, results), read while it still holds the
// adapter (m_call): another thread's call is refused meanwhile, never handed this one's
// results, and a close() from another thread waits, so nothing is read after it was freed.
// A field may be device memory (tessera/_arrays.py DeviceArray): its address goes in as any
// other, and the producer's stream, when the package passes one, is the CUDA stream of that
// call only (the adapter's own, set_cuda_stream, is put back after it).
#include "binding_support.h"

#include <tessera/adapter.h>

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace tessera::python {
namespace {

using Int3 = std::array<std::int64_t, 3>;
using Double3 = std::array<double, 3>;
/// name, data address, dtype code, dims, byte strides, ghosts low, ghosts high
using FieldTuple = std::tuple<std::string, std::uintptr_t, int, Int3, Int3, Int3, Int3>;
/// A rectilinear axis' coordinates, read in place (tessera/_arrays.py coordinate_array)
using CoordArray = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
/// x, y, z addresses, dtype code, byte stride, count (tessera/_mesh_domains.py _coords)
using CoordsetTuple = std::tuple<std::uintptr_t, std::uintptr_t, std::uintptr_t, int, std::int64_t, std::int64_t>;
/// association, coordinates, dims, shape, connectivity address, index dtype, ncells, fields,
/// ghost field name (tessera/_mesh_domains.py _domain)
using MeshDomainTuple = std::tuple<int, CoordsetTuple, Int3, int, std::uintptr_t, int, std::int64_t,
                                   std::vector<FieldTuple>, std::optional<std::string>>;

/// The C descriptors of the fields (names point into `fields`).
std::vector<tessera_field> descriptors(const std::vector<FieldTuple>& fields) {
  std::vector<tessera_field> descs(fields.size());
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const auto& [name, data, dtype, dims, strides, lo, hi] = fields[f];
    tessera_field& d = descs[f];
    require_no_nul(name, "field name");
    d.name = name.c_str();
    d.data = reinterpret_cast<const void*>(data);
    d.dtype = static_cast<tessera_dtype>(dtype);
    for (int a = 0; a < 3; ++a) {
      d.dims[a] = dims[a];
      d.byte_strides[a] = strides[a];
      d.ghosts_lo[a] = lo[a];
      d.ghosts_hi[a] = hi[a];
    }
  }
  return descs;
}

/// The C descriptors of curvilinear and unstructured domains; `fields` holds their field
/// descriptors (names point into `domains`' strings, ghost names likewise).
std::vector<tessera_mesh_domain> mesh_descriptors(const std::vector<MeshDomainTuple>& domains,
                                                  std::vector<std::vector<tessera_field>>& fields) {
  std::vector<tessera_mesh_domain> descs(domains.size());
  fields.resize(domains.size());
  for (std::size_t d = 0; d < domains.size(); ++d) {
    const auto& [association, coords, dims, shape, connectivity, index_dtype, ncells, list, ghost] = domains[d];
    if (association != 0 && association != 1) throw nb::value_error("association: 0 (vertex) or 1 (cell)");
    tessera_mesh_domain& m = descs[d];
    m.association = static_cast<tessera_association>(association);
    const auto& [x, y, z, dtype, stride, count] = coords;
    m.coords.x = reinterpret_cast<const void*>(x);
    m.coords.y = reinterpret_cast<const void*>(y);
    m.coords.z = reinterpret_cast<const void*>(z);
    m.coords.dtype = static_cast<tessera_dtype>(dtype);
    m.coords.byte_stride = stride;
    m.coords.count = count;
    for (int a = 0; a < 3; ++a) m.dims[a] = dims[a];
    m.shape = static_cast<tessera_shape>(shape);
    m.connectivity = reinterpret_cast<const void*>(connectivity);
    m.index_dtype = static_cast<tessera_dtype>(index_dtype);
    m.ncells = ncells;
    fields[d] = descriptors(list);
    m.fields = fields[d].data();
    m.nfields = static_cast<int>(fields[d].size());
    if (ghost) require_no_nul(*ghost, "ghost_field");
    m.ghost_field = ghost ? ghost->c_str() : nullptr;
  }
  return descs;
}

/// The refused call's message, in the C++ Adapter's words (agreement/call_gate.cpp).
std::string refusal(const char* function, bool closing) {
  return std::string(function) + ": refused: " +
         (closing ? "adapter is being closed by another thread (this call did nothing)"
                  : "another thread is inside a call on this adapter (calls on one adapter must not overlap; this "
                    "call did nothing)");
}

class PyAdapter {
 public:
  /// Opens (collective); the package has loaded the config and the ranks have agreed first.
  PyAdapter(const std::string& source, bool is_text, const std::string& name, int comm_f, const std::string& output_dir,
            bool quiet) {
    if (!is_text) require_no_nul(source, "config");
    require_no_nul(output_dir, "output_dir");
    insitu::OpenOptions options;
    options.output_dir = output_dir;
    if (is_text) options.yaml_text = source;
    m_adapter.set_quiet(quiet);
    tessera_status s;
    {
      nb::gil_scoped_release unlocked;
      s = m_adapter.open(is_text ? name : source, comm_f, options);
    }
    if (s != TESSERA_OK) throw error_for_status(s, m_adapter.last_error());
  }

  /// Whether execute at `step` would evaluate any render (Adapter::fires); true while another
  /// thread is inside a call (that call's refusal then tells).
  bool fires(std::int64_t step, bool final_step) {
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    return !call.owns_lock() || m_adapter.fires(step, final_step);
  }

  /// Returns (status, message, results) of this call; with `on_error: abort` a failure raises.
  nb::tuple execute(std::int64_t step, double time, Double3 origin, Double3 spacing, Int3 global_dims, Int3 offset,
                    const std::vector<FieldTuple>& fields, bool final_step, std::optional<std::uintptr_t> stream) {
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    if (!call.owns_lock()) return refused(final_step ? "execute (final step)" : "execute");
    tessera_grid grid{};
    for (int a = 0; a < 3; ++a) {
      grid.origin[a] = origin[a];
      grid.spacing[a] = spacing[a];
      grid.global_dims[a] = global_dims[a];
      grid.offset[a] = offset[a];
    }
    const std::vector<tessera_field> descs = descriptors(fields);
    // Put back after the outcome is read (the return value is built before locals go): setting
    // the stream clears the adapter's last error
    const CallStream on(m_adapter, stream, m_stream);
    tessera_status s;
    try {
      nb::gil_scoped_release unlocked;
      s = m_adapter.execute(step, time, grid, descs, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
    return outcome(s);
  }

  /// execute_domains: the mesh (association 0 vertex / 1 cell, origin, spacing, per axis None
  /// for a uniform axis or the float64 coordinates, global_dims, nlevels and the nlevels - 1
  /// refinement ratios) and the domains (level, offset, fields as in execute(), and either no
  /// associations (every field the mesh's) or one per field, 0 vertex / 1 cell). The lengths
  /// the C side reads (coordinates, ratios) are checked here too: nothing past an array.
  nb::tuple execute_domains(
      std::int64_t step, double time, int association, Double3 origin, Double3 spacing,
      const std::array<std::optional<CoordArray>, 3>& coords, Int3 global_dims, int nlevels,
      const std::vector<int>& refinement,
      const std::vector<std::tuple<int, Int3, std::vector<FieldTuple>, std::vector<int>>>& domains, bool final_step,
      std::optional<std::uintptr_t> stream) {
    if (nlevels < 1 || refinement.size() != static_cast<std::size_t>(nlevels - 1))
      throw nb::value_error("refinement: nlevels - 1 ratios are needed");
    if (association != 0 && association != 1) throw nb::value_error("association: 0 (vertex) or 1 (cell)");
    for (int a = 0; a < 3; ++a) {
      const std::int64_t n = global_dims[a];
      if (coords[a] && (n < 0 || coords[a]->shape(0) != static_cast<std::uint64_t>(n) + (association == 1 ? 1 : 0)))
        throw nb::value_error(("coords[" + std::to_string(a) + "]: " + std::to_string(coords[a]->shape(0)) +
                               " values for global_dims[" + std::to_string(a) + "] = " + std::to_string(n))
                                  .c_str());
    }
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    if (!call.owns_lock()) return refused(final_step ? "execute_domains (final step)" : "execute_domains");
    tessera_mesh mesh{};
    mesh.association = static_cast<tessera_association>(association);
    mesh.nlevels = nlevels;
    mesh.refinement = refinement.empty() ? nullptr : refinement.data();
    for (int a = 0; a < 3; ++a) {
      mesh.origin[a] = origin[a];
      mesh.spacing[a] = spacing[a];
      mesh.coords[a] = coords[a] ? coords[a]->data() : nullptr;
      mesh.global_dims[a] = global_dims[a];
    }
    std::vector<std::vector<tessera_field>> fields(domains.size());
    std::vector<std::vector<tessera_association>> associations(domains.size());
    std::vector<tessera_domain> descs(domains.size());
    for (std::size_t d = 0; d < domains.size(); ++d) {
      const auto& [level, offset, list, assoc] = domains[d];
      if (!assoc.empty() && assoc.size() != list.size())
        throw nb::value_error("associations: none or one per field are needed");
      for (int a : assoc) {
        if (a != 0 && a != 1) throw nb::value_error("associations: 0 (vertex) or 1 (cell)");
        associations[d].push_back(static_cast<tessera_association>(a));
      }
      descs[d].associations = associations[d].empty() ? nullptr : associations[d].data();
      fields[d] = descriptors(list);
      descs[d].level = level;
      for (int a = 0; a < 3; ++a) descs[d].offset[a] = offset[a];
      descs[d].fields = fields[d].data();
      descs[d].nfields = static_cast<int>(fields[d].size());
    }
    // Put back after the outcome is read (the return value is built before locals go): setting
    // the stream clears the adapter's last error
    const CallStream on(m_adapter, stream, m_stream);
    tessera_status s;
    try {
      nb::gil_scoped_release unlocked;
      s = m_adapter.execute_domains(step, time, mesh, descs, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
    return outcome(s);
  }

  /// execute_mesh_domains: curvilinear and unstructured domains, described by the package
  /// (tessera/_mesh_domains.py), which checked every length C reads against its array.
  nb::tuple execute_mesh_domains(std::int64_t step, double time, const std::vector<MeshDomainTuple>& domains,
                                 bool final_step, std::optional<std::uintptr_t> stream) {
    std::vector<std::vector<tessera_field>> fields;
    const std::vector<tessera_mesh_domain> descs = mesh_descriptors(domains, fields);
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    if (!call.owns_lock()) return refused(final_step ? "execute_mesh_domains (final step)" : "execute_mesh_domains");
    // Put back after the outcome is read (the return value is built before locals go): setting
    // the stream clears the adapter's last error
    const CallStream on(m_adapter, stream, m_stream);
    tessera_status s;
    try {
      nb::gil_scoped_release unlocked;
      s = m_adapter.execute_mesh_domains(step, time, descs, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
    return outcome(s);
  }

  /// execute_refused: this rank's arguments could not be described (the package raised); the
  /// rank still takes part in the collective call `kind` (0 execute, 1 domains, 2 mesh
  /// domains) so that the other ranks fail with `reason` instead of waiting.
  nb::tuple execute_refused(std::int64_t step, double time, int kind, const std::string& reason, bool final_step) {
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    if (!call.owns_lock()) return refused(final_step ? "execute (final step)" : "execute");
    tessera_status s;
    try {
      nb::gil_scoped_release unlocked;
      s = m_adapter.execute_refused(step, time, kind, reason, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
    return outcome(s);
  }

  /// Adapter::set_cuda_stream (0: none, the whole device is synchronised); returns (status,
  /// message). Refused like a call while another thread's call holds the adapter.
  nb::tuple set_cuda_stream(std::uintptr_t stream) {
    std::unique_lock<std::mutex> call(m_call, std::try_to_lock);
    if (!call.owns_lock()) return refused("set_cuda_stream");
    const tessera_status s = m_adapter.set_cuda_stream(reinterpret_cast<void*>(stream));
    if (s == TESSERA_OK) m_stream = stream;
    return nb::make_tuple(static_cast<int>(s), text(m_adapter.last_error()));
  }

  /// Waits (GIL released) for a call another Python thread is making on this adapter, then
  /// closes; returns (status, message) (with MPI, a rank that disagreed about the calls is
  /// reported). Calls arriving meanwhile are refused as "being closed".
  nb::tuple close() {
    m_closing = true;
    int s;
    std::string message;
    {
      nb::gil_scoped_release unlocked;
      std::lock_guard<std::mutex> call(m_call);
      s = m_adapter.close();
      message = m_adapter.last_error();
    }
    return nb::make_tuple(s, text(message));
  }

  bool is_open() {
    nb::gil_scoped_release unlocked;
    std::lock_guard<std::mutex> call(m_call);
    return m_adapter.is_open();
  }

 private:
  /// A call refused because another thread's call (or close) holds m_call: nothing done, no
  /// results (not the other call's).
  nb::tuple refused(const char* function) const {
    return nb::make_tuple(static_cast<int>(TESSERA_ERROR_CONFIG), text(refusal(function, m_closing)), nb::list());
  }

  /// (status, message, results) of the call that holds m_call, read before it lets go: the
  /// renders of that call, one dict each; `image`: a float32 (H, W, 4) copy of the image on
  /// rank 0 when the render succeeded, else None.
  nb::tuple outcome(tessera_status status) const {
    nb::list out;
    for (const insitu::RenderResult& r : m_adapter.last_results()) {
      nb::dict d;
      d["name"] = text(r.name);
      d["step"] = r.step;
      d["time"] = r.time;
      d["status"] = static_cast<int>(r.status);
      d["error"] = text(r.error);
      nb::list files, warnings;
      for (const std::string& f : r.files) files.append(text(f));
      for (const std::string& w : r.warnings) warnings.append(text(w));
      d["files"] = files;
      d["render_seconds"] = r.render_seconds;
      d["prepare_seconds"] = r.prepare_seconds;
      d["samples_per_second"] = r.samples_per_second;
      d["simulation_seconds"] = r.simulation_seconds;
      d["cost_ratio"] = r.cost_ratio;
      d["warnings"] = warnings;
      d["planned_spp"] = r.planned_spp;
      d["actual_spp"] = r.actual_spp;
      d["budget_skipped"] = r.budget_skipped;
      d["budget_balance"] = r.budget_balance;
      d["budget_ratio"] = r.budget_ratio;
      d["device"] = text(r.device);  // "cpu" or "cuda:N"
      d["bytes_to_device"] = r.stats.bytes_to_device;
      d["bytes_to_host"] = r.stats.bytes_to_host;
      d["mesh_layout_reused"] = r.mesh_layout_reused;
      d["mesh_values_only"] = r.mesh_values_only;
      d["mesh_summary_shared"] = r.mesh_summary_shared;
      d["mesh_exchange_bytes"] = r.mesh_exchange_bytes;
      // (a render the budget skipped has no image of this step)
      const Image* img = r.status == TESSERA_OK && !r.budget_skipped ? m_adapter.last_image(r.name) : nullptr;
      if (img) {
        const std::size_t shape[3] = {static_cast<std::size_t>(img->height), static_cast<std::size_t>(img->width), 4};
        nb::ndarray<nb::numpy, const float, nb::ndim<3>> view(img->rgba.data(), 3, shape, nb::handle());
        d["image"] = nb::cast(view, nb::rv_policy::copy);
      } else {
        d["image"] = nb::none();
      }
      out.append(d);
    }
    return nb::make_tuple(static_cast<int>(status), text(m_adapter.last_error()), out);
  }

  /// The producer's stream for one call (a field's __cuda_array_interface__ stream), set
  /// before it and the adapter's own (`kept`) put back when this goes out of scope, also when
  /// the call throws; declared before the call's outcome is read, since
  /// Adapter::set_cuda_stream clears last_error().
  struct CallStream {
    CallStream(insitu::Adapter& adapter, std::optional<std::uintptr_t> stream, std::uintptr_t kept)
        : m_adapter(adapter), m_kept(kept), m_set(stream.has_value()) {
      if (m_set) m_adapter.set_cuda_stream(reinterpret_cast<void*>(*stream));
    }
    ~CallStream() {
      if (m_set) m_adapter.set_cuda_stream(reinterpret_cast<void*>(m_kept));
    }
    CallStream(const CallStream&) = delete;
    CallStream& operator=(const CallStream&) = delete;
    insitu::Adapter& m_adapter;
    std::uintptr_t m_kept;
    bool m_set;
  };

  insitu::Adapter m_adapter;
  std::uintptr_t m_stream = 0;  ///< the last set_cuda_stream's (0: none); guarded by m_call
  /// Held by a call from its start until its outcome is read (so that a call's results are
  /// its own), and by close() while it closes; a call that finds it held is refused, as the
  /// Adapter refuses overlapping calls. Never held while waiting for the GIL by close.
  std::mutex m_call;
  std::atomic<bool> m_closing{false};  ///< close() has begun: refusals say so
};

}  // namespace

void register_adapter(nb::module_& m) {
  nb::class_<PyAdapter>(m, "Adapter")
      .def(nb::init<const std::string&, bool, const std::string&, int, const std::string&, bool>(), nb::arg("source"),
           nb::arg("is_text"), nb::arg("name"), nb::arg("comm_f"), nb::arg("output_dir"), nb::arg("quiet"))
      .def("execute", &PyAdapter::execute, nb::arg("step"), nb::arg("time"), nb::arg("origin"), nb::arg("spacing"),
           nb::arg("global_dims"), nb::arg("offset"), nb::arg("fields"), nb::arg("final_step"),
           nb::arg("stream").none() = nb::none())
      .def("execute_domains", &PyAdapter::execute_domains, nb::arg("step"), nb::arg("time"), nb::arg("association"),
           nb::arg("origin"), nb::arg("spacing"), nb::arg("coords"), nb::arg("global_dims"), nb::arg("nlevels"),
           nb::arg("refinement"), nb::arg("domains"), nb::arg("final_step"), nb::arg("stream").none() = nb::none())
      .def("execute_mesh_domains", &PyAdapter::execute_mesh_domains, nb::arg("step"), nb::arg("time"),
           nb::arg("domains"), nb::arg("final_step"), nb::arg("stream").none() = nb::none())
      .def("execute_refused", &PyAdapter::execute_refused, nb::arg("step"), nb::arg("time"), nb::arg("kind"),
           nb::arg("reason"), nb::arg("final_step"))
      .def("fires", &PyAdapter::fires, nb::arg("step"), nb::arg("final_step"))
      .def("set_cuda_stream", &PyAdapter::set_cuda_stream, nb::arg("stream"))
      .def("close", &PyAdapter::close)
      .def("is_open", &PyAdapter::is_open);
}

}  // namespace tessera::python
