// tessera._tessera.Adapter: tessera.Adapter's C++ half over tessera::insitu::Adapter (the C
// API's own implementation). Open, execute and close run with the GIL released; the fields
// arrive as descriptors of the caller's arrays (tessera/_arrays.py), read in place. A close()
// from another Python thread waits for a running execute (the Adapter's gate) and for the
// accessors (m_state), so nothing is read after it was freed.
#include "binding_support.h"

#include <tessera/adapter.h>

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <new>
#include <string>
#include <tuple>
#include <vector>

namespace tessera::python {
namespace {

using Int3 = std::array<std::int64_t, 3>;
using Double3 = std::array<double, 3>;
/// name, data address, dtype code, dims, byte strides, ghosts low, ghosts high
using FieldTuple = std::tuple<std::string, std::uintptr_t, int, Int3, Int3, Int3, Int3>;

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

class PyAdapter {
 public:
  /// Validates the config here first (a ConfigError with its key path), then opens.
  PyAdapter(const std::string& source, bool is_text, const std::string& name, int comm_f, const std::string& output_dir,
            bool quiet) {
    if (!is_text) require_no_nul(source, "config");
    require_no_nul(output_dir, "output_dir");
    load_config_source(source, is_text, name);
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

  /// Returns the status; with `on_error: abort` a failure raises instead.
  int execute(std::int64_t step, double time, Double3 origin, Double3 spacing, Int3 global_dims, Int3 offset,
              const std::vector<FieldTuple>& fields, bool final_step) {
    tessera_grid grid{};
    for (int a = 0; a < 3; ++a) {
      grid.origin[a] = origin[a];
      grid.spacing[a] = spacing[a];
      grid.global_dims[a] = global_dims[a];
      grid.offset[a] = offset[a];
    }
    const std::vector<tessera_field> descs = descriptors(fields);
    try {
      nb::gil_scoped_release unlocked;
      return m_adapter.execute(step, time, grid, descs, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
  }

  /// execute_domains: the mesh (association 0 vertex / 1 cell, origin, spacing, per axis the
  /// address of a float64 coordinate array or 0 for a uniform axis, whose length the caller has
  /// checked, global_dims, nlevels and the nlevels - 1 refinement ratios, whose count the
  /// caller has checked) and the domains (level, offset, fields as in execute()).
  int execute_domains(std::int64_t step, double time, int association, Double3 origin, Double3 spacing,
                      std::array<std::uintptr_t, 3> coords, Int3 global_dims, int nlevels,
                      const std::vector<int>& refinement,
                      const std::vector<std::tuple<int, Int3, std::vector<FieldTuple>>>& domains, bool final_step) {
    if (nlevels < 1 || refinement.size() != static_cast<std::size_t>(nlevels - 1))
      throw nb::value_error("refinement: nlevels - 1 ratios are needed");
    tessera_mesh mesh{};
    mesh.association = static_cast<tessera_association>(association);
    mesh.nlevels = nlevels;
    mesh.refinement = refinement.empty() ? nullptr : refinement.data();
    for (int a = 0; a < 3; ++a) {
      mesh.origin[a] = origin[a];
      mesh.spacing[a] = spacing[a];
      mesh.coords[a] = reinterpret_cast<const double*>(coords[a]);
      mesh.global_dims[a] = global_dims[a];
    }
    std::vector<std::vector<tessera_field>> fields(domains.size());
    std::vector<tessera_domain> descs(domains.size());
    for (std::size_t d = 0; d < domains.size(); ++d) {
      const auto& [level, offset, list] = domains[d];
      fields[d] = descriptors(list);
      descs[d].level = level;
      for (int a = 0; a < 3; ++a) descs[d].offset[a] = offset[a];
      descs[d].fields = fields[d].data();
      descs[d].nfields = static_cast<int>(fields[d].size());
    }
    try {
      nb::gil_scoped_release unlocked;
      return m_adapter.execute_domains(step, time, mesh, descs, final_step);
    } catch (const insitu::AdapterError& e) {
      throw error_for_status(e.status(), e.what());
    }
  }

  /// Waits (GIL released) for a call another Python thread is making on this adapter, then
  /// closes; returns the status (with MPI, a rank that disagreed about the calls is reported).
  int close() {
    nb::gil_scoped_release unlocked;
    std::lock_guard<std::mutex> lock(m_state);
    return m_adapter.close();
  }

  std::string last_error() const {
    auto lock = lock_state();
    return m_adapter.last_error();
  }
  bool is_open() const {
    auto lock = lock_state();
    return m_adapter.is_open();
  }

  /// The renders of the last execute, one dict each; `image`: a float32 (H, W, 4) copy of the
  /// image on rank 0 when the render succeeded, else None.
  nb::list results() const {
    auto lock = lock_state();
    nb::list out;
    for (const insitu::RenderResult& r : m_adapter.last_results()) {
      nb::dict d;
      d["name"] = r.name;
      d["step"] = r.step;
      d["time"] = r.time;
      d["status"] = static_cast<int>(r.status);
      d["error"] = r.error;
      d["files"] = nb::cast(r.files);
      d["render_seconds"] = r.render_seconds;
      d["prepare_seconds"] = r.prepare_seconds;
      d["samples_per_second"] = r.samples_per_second;
      d["simulation_seconds"] = r.simulation_seconds;
      d["cost_ratio"] = r.cost_ratio;
      d["warnings"] = nb::cast(r.warnings);
      d["planned_spp"] = r.planned_spp;
      d["actual_spp"] = r.actual_spp;
      d["budget_skipped"] = r.budget_skipped;
      d["budget_balance"] = r.budget_balance;
      d["budget_ratio"] = r.budget_ratio;
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
    return out;
  }

 private:
  /// The state the last call left (results, message) against a close() on another thread:
  /// taken with the GIL released, and never held while waiting for the GIL.
  std::unique_lock<std::mutex> lock_state() const {
    nb::gil_scoped_release unlocked;
    return std::unique_lock<std::mutex>(m_state);
  }

  insitu::Adapter m_adapter;
  mutable std::mutex m_state;  ///< held by close() and while the accessors read
};

}  // namespace

void register_adapter(nb::module_& m) {
  nb::class_<PyAdapter>(m, "Adapter")
      .def(nb::init<const std::string&, bool, const std::string&, int, const std::string&, bool>(), nb::arg("source"),
           nb::arg("is_text"), nb::arg("name"), nb::arg("comm_f"), nb::arg("output_dir"), nb::arg("quiet"))
      .def("execute", &PyAdapter::execute, nb::arg("step"), nb::arg("time"), nb::arg("origin"), nb::arg("spacing"),
           nb::arg("global_dims"), nb::arg("offset"), nb::arg("fields"), nb::arg("final_step"))
      .def("execute_domains", &PyAdapter::execute_domains, nb::arg("step"), nb::arg("time"), nb::arg("association"),
           nb::arg("origin"), nb::arg("spacing"), nb::arg("coords"), nb::arg("global_dims"), nb::arg("nlevels"),
           nb::arg("refinement"), nb::arg("domains"), nb::arg("final_step"))
      .def("close", &PyAdapter::close)
      .def("last_error", &PyAdapter::last_error)
      .def("is_open", &PyAdapter::is_open)
      .def("results", &PyAdapter::results);
}

}  // namespace tessera::python
