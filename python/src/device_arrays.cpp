// tessera._tessera's side of the package's device arrays (tessera/_arrays.py): a DLPack
// tensor's description (address, dtype, shape, byte strides, device) read through nanobind's
// DLPack import, never its values, and whether this build holds the CUDA backend.
#include "binding_support.h"

#include <tessera/cuda_render.h>

#include <nanobind/ndarray.h>
#include <nanobind/stl/vector.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace tessera::python {
namespace {

/// A DLPack tensor (an object with __dlpack__, or a capsule) held while its address is used:
/// the tensor's deleter runs when this object is released (tessera/_arrays.py keeps it with
/// the field). Only the description is read; its memory may be on a device.
class DLPackTensor {
 public:
  explicit DLPackTensor(nb::ndarray<nb::ro> tensor) : m_tensor(std::move(tensor)) {}

  /// The first element's address (the tensor's data plus its byte_offset).
  std::uintptr_t address() const { return reinterpret_cast<std::uintptr_t>(m_tensor.data()); }
  int dtype_code() const { return m_tensor.dtype().code; }  ///< DLDataTypeCode: 0 int, 1 uint, 2 float, ...
  int bits() const { return m_tensor.dtype().bits; }
  int lanes() const { return m_tensor.dtype().lanes; }
  int device_type() const { return m_tensor.device_type(); }  ///< DLDeviceType: 1 CPU, 2 CUDA, 13 managed, ...
  int device_id() const { return m_tensor.device_id(); }
  std::vector<std::int64_t> shape() const {
    std::vector<std::int64_t> out(m_tensor.ndim());
    for (std::size_t a = 0; a < out.size(); ++a) out[a] = static_cast<std::int64_t>(m_tensor.shape(a));
    return out;
  }
  /// In bytes (DLPack counts strides in elements; a tensor without strides is C-contiguous,
  /// and nanobind fills them in).
  std::vector<std::int64_t> byte_strides() const {
    const std::int64_t size = (static_cast<std::int64_t>(bits()) * lanes() + 7) / 8;
    std::vector<std::int64_t> out(m_tensor.ndim());
    for (std::size_t a = 0; a < out.size(); ++a) out[a] = m_tensor.stride(a) * size;
    return out;
  }

 private:
  nb::ndarray<nb::ro> m_tensor;
};

}  // namespace

void register_device_arrays(nb::module_& m) {
  nb::class_<DLPackTensor>(m, "_DLPackTensor")
      .def_prop_ro("address", &DLPackTensor::address)
      .def_prop_ro("dtype_code", &DLPackTensor::dtype_code)
      .def_prop_ro("bits", &DLPackTensor::bits)
      .def_prop_ro("lanes", &DLPackTensor::lanes)
      .def_prop_ro("device_type", &DLPackTensor::device_type)
      .def_prop_ro("device_id", &DLPackTensor::device_id)
      .def_prop_ro("shape", &DLPackTensor::shape)
      .def_prop_ro("byte_strides", &DLPackTensor::byte_strides);
  // The tensor of `source` (its __dlpack__() or the capsule itself); TypeError when nanobind
  // cannot import it (tessera/_arrays.py names the field)
  m.def(
      "_dlpack_tensor", [](nb::ndarray<nb::ro> tensor) { return DLPackTensor(std::move(tensor)); },
      nb::arg("source").noconvert());
  m.def("cuda_built", [] { return cuda_built(); });
}

}  // namespace tessera::python
