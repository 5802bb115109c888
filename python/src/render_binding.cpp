// tessera._tessera.render_array: tessera.render's C++ half. The config's render through the
// CLI's own render job (job/include/tessera/job/render_job.h: scene, memory check, time
// limit, prepare, render), on a field view of the caller's array: no copy.
#include "binding_support.h"

#include <tessera/cuda_render.h>
#include <tessera/image_io.h>
#include <tessera/job/render_job.h>

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tessera::python {
namespace {

using Int3 = std::array<std::int64_t, 3>;
using Double3 = std::array<double, 3>;

/// The render `name` (non-empty) or at `index` (>= 0), else the first.
const config::RenderSpec& select_render(const config::Config& cfg, const std::string& name, std::int64_t index) {
  std::string names;
  for (const auto& r : cfg.renders) names += (names.empty() ? "" : ", ") + r.name;
  if (!name.empty()) {
    if (const auto* r = cfg.find_render(name)) return *r;
    throw std::invalid_argument("render '" + name + "': no such render in " + cfg.path + " (renders: " + names + ")");
  }
  if (index >= static_cast<std::int64_t>(cfg.renders.size()))
    throw std::invalid_argument("render " + std::to_string(index) + ": " + cfg.path + " has " +
                                std::to_string(cfg.renders.size()) + " render(s) (" + names + ")");
  return cfg.renders[index < 0 ? 0 : static_cast<std::size_t>(index)];
}

/// An owning float32 (height, width, 4) numpy array over the image's pixels (moved, not copied).
nb::object to_numpy(std::vector<float>&& rgba, int width, int height) {
  auto* pixels = new std::vector<float>(std::move(rgba));
  nb::capsule owner(pixels, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
  const std::size_t shape[3] = {static_cast<std::size_t>(height), static_cast<std::size_t>(width), 4};
  return nb::cast(nb::ndarray<nb::numpy, float, nb::ndim<3>>(pixels->data(), 3, shape, owner));
}

/// Refuses a device (or managed) array: the render job reads the volume on the host. Asked
/// only for an array that came through a CUDA protocol (`data` may still be host memory).
void require_host_memory(std::uintptr_t data) {
  MemoryKind kind;
  try {
    kind = cuda_memory_kind(reinterpret_cast<const void*>(data));
  } catch (const std::exception& e) {
    throw error_for_status(TESSERA_ERROR_DATA, std::string("volume: where its memory lives is unknown: ") + e.what());
  }
  if (kind != MemoryKind::Host)
    throw error_for_status(TESSERA_ERROR_DATA,
                           std::string("volume: ") + (kind == MemoryKind::Device ? "device" : "managed") +
                               " memory: tessera.render reads host arrays; a device array is rendered in place by "
                               "tessera.Adapter.execute (tessera.device: auto or cuda, docs/gpu_bindings.md), or "
                               "pass a host copy (cupy.asnumpy(a), t.cpu().numpy())");
}

/// Returns (image, warnings, address of the first vertex the renderer read). `device_protocol`:
/// the array came as __cuda_array_interface__ or DLPack CUDA (its memory is asked about).
nb::tuple render_array(const std::string& source, bool is_text, const std::string& name, const std::string& render_name,
                       std::int64_t render_index, std::uintptr_t data, int dtype, Int3 dims, Int3 byte_strides,
                       std::optional<Double3> spacing, std::optional<Double3> origin, std::int64_t step,
                       bool device_protocol) {
  if (!is_text) require_no_nul(source, "config");
  require_no_nul(render_name, "render");
  const config::Config cfg = load_config_source(source, is_text, name);
  const config::RenderSpec& spec = select_render(cfg, render_name, render_index);
  if (dtype < 0 || dtype > static_cast<int>(DType::Float64)) throw std::invalid_argument("dtype code out of range");
  if (device_protocol) require_host_memory(data);

  // Geometry: the arguments, else the config's volume: block (a CLI scene file), else unit
  VolumeGeometry geometry = cfg.volume ? cfg.volume->geometry() : VolumeGeometry{Vec3(0.0), Vec3(1.0)};
  if (spacing) geometry.spacing = Vec3((*spacing)[0], (*spacing)[1], (*spacing)[2]);
  if (origin) geometry.origin = Vec3((*origin)[0], (*origin)[1], (*origin)[2]);

  FieldView view;
  view.data = reinterpret_cast<const void*>(data);
  view.dtype = static_cast<DType>(dtype);
  for (int a = 0; a < 3; ++a) {
    view.dims[a] = dims[a];
    view.byte_strides[a] = byte_strides[a];
  }

  job::RenderedImage rendered;
  std::uintptr_t seen = 0;
  {
    nb::gil_scoped_release unlocked;
    job::VolumeInfo info;
    try {
      for (int a = 0; a < 3; ++a)
        if (!(geometry.spacing[a] > 0.0) || !std::isfinite(geometry.spacing[a]) || !std::isfinite(geometry.origin[a]))
          throw std::invalid_argument("spacing must be finite and > 0 and origin finite on each axis");
      info = job::describe_field(view, geometry, spec.integrator.desc);
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw error_for_status(TESSERA_ERROR_DATA, e.what());
    }
    seen = reinterpret_cast<std::uintptr_t>(info.view.data);
    try {
      job::Args args;
      args.step = step;  // the random numbers of this step, as the adapter and tessera-render --step
      rendered = job::render_image(cfg, spec, info, args, {}, false);
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw error_for_status(TESSERA_ERROR_RENDER, e.what());
    }
  }
  const int w = rendered.image.width, h = rendered.image.height;
  return nb::make_tuple(to_numpy(std::move(rendered.image.rgba), w, h), nb::cast(rendered.record.warnings), seen);
}

}  // namespace

/// An EXR's RGBA as float32 (height, width, 4), for the tests' comparisons with tessera-render.
nb::object read_exr_rgba(const std::string& path) {
  Image img;
  try {
    img = read_exr(path);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw error_for_status(TESSERA_ERROR_IO, e.what());
  }
  return to_numpy(std::move(img.rgba), img.width, img.height);
}

void register_render(nb::module_& m) {
  m.def("_read_exr", &read_exr_rgba, nb::arg("path"));
  m.def("render_array", &render_array, nb::arg("source"), nb::arg("is_text"), nb::arg("name"), nb::arg("render_name"),
        nb::arg("render_index"), nb::arg("data"), nb::arg("dtype"), nb::arg("dims"), nb::arg("byte_strides"),
        nb::arg("spacing").none(), nb::arg("origin").none(), nb::arg("step"), nb::arg("device_protocol") = false);
}

}  // namespace tessera::python
