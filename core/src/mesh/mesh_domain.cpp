/// The small helpers of mesh.h: shapes and a domain's cell count.
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

}  // namespace tessera
