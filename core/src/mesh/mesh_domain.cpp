/// The small helpers of mesh.h: shapes, a domain's cell count and its arrays by slot.
#include <tessera/mesh.h>

namespace tessera {

int shape_vertex_count(Shape shape) {
  switch (shape) {
    case Shape::Hex: return 8;
    case Shape::Tet: return 4;
    case Shape::Wedge: return 6;
    case Shape::Pyramid: return 5;
  }
  return 0;
}

const char* shape_name(Shape shape) {
  switch (shape) {
    case Shape::Hex: return "hex";
    case Shape::Tet: return "tet";
    case Shape::Wedge: return "wedge";
    case Shape::Pyramid: return "pyramid";
  }
  return "unknown shape";
}

std::int64_t MeshDomain::cell_count() const {
  if (!structured()) return ncells;
  return (dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1);
}

MeshArraySpan mesh_array(const MeshDomain& d, MeshArraySlot s) {
  // count elements of `size` bytes, byte_stride apart
  const auto span = [](const void* p, std::int64_t count, std::int64_t stride, std::int64_t size, const char* name) {
    if (!p || count <= 0) return MeshArraySpan{nullptr, 0, name};
    return MeshArraySpan{p, (count - 1) * stride + size, name};
  };
  const MeshCoords& c = d.coords;
  const auto csize = static_cast<std::int64_t>(dtype_size(c.dtype));
  switch (s) {
    case MeshArraySlot::X: return span(c.x, c.count, c.byte_stride, csize, "coords.x");
    case MeshArraySlot::Y: return span(c.y, c.count, c.byte_stride, csize, "coords.y");
    case MeshArraySlot::Z: return span(c.z, c.count, c.byte_stride, csize, "coords.z");
    case MeshArraySlot::Connectivity: {
      if (d.structured()) return MeshArraySpan{nullptr, 0, "the connectivity"};
      const std::int64_t isize = d.index_type == IndexType::Int64 ? 8 : 4;
      return span(d.connectivity, d.ncells * shape_vertex_count(d.shape), isize, isize, "the connectivity");
    }
    case MeshArraySlot::Field:
      return span(d.field.data, d.field.count, d.field.byte_stride,
                  static_cast<std::int64_t>(dtype_size(d.field.dtype)), "the field");
    case MeshArraySlot::Ghosts: return span(d.ghosts.data, d.ghosts.count, d.ghosts.byte_stride, 1, "the ghost mask");
  }
  return {};
}

void set_mesh_array(MeshDomain& d, MeshArraySlot s, const void* data) {
  switch (s) {
    case MeshArraySlot::X: d.coords.x = data; break;
    case MeshArraySlot::Y: d.coords.y = data; break;
    case MeshArraySlot::Z: d.coords.z = data; break;
    case MeshArraySlot::Connectivity: d.connectivity = data; break;
    case MeshArraySlot::Field: d.field.data = data; break;
    case MeshArraySlot::Ghosts: d.ghosts.data = static_cast<const std::uint8_t*>(data); break;
  }
}

}  // namespace tessera
