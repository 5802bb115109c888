#pragma once
/// Test input for the core's refinement levels (tessera::AmrField, without the C API): a
/// hierarchy whose float64 patches own their values, each a function of the world position of
/// its samples.
#include <tessera/amr.h>
#include <tessera/scene.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace tessera_test {

/// A value at a world position.
using PositionFn = std::function<double(const tessera::Vec3&)>;

/// A hierarchy whose patches own their (float64, C order) values: f at each sample's world
/// position (a vertex, or a cell's centre), level 0 placed at origin with spacing h.
struct AmrHierarchy {
  tessera::AmrField field;
  tessera::Association assoc = tessera::Association::Vertex;
  tessera::Vec3 origin{0.0}, h{1.0};
  std::vector<std::vector<double>> data;
  std::vector<tessera::AmrPatch> patches;

  AmrHierarchy(const std::int64_t dims[3], tessera::Association a, std::vector<int> ratios, tessera::Vec3 o,
               tessera::Vec3 hh)
      : assoc(a), origin(o), h(hh) {
    for (int k = 0; k < 3; ++k) field.dims[k] = dims[k];
    field.dtype = tessera::DType::Float64;
    field.nlevels = static_cast<int>(ratios.size()) + 1;
    for (std::size_t l = 0; l < ratios.size(); ++l) field.ratio[l] = ratios[l];
  }
  /// World position of sample idx of level l.
  tessera::Vec3 position(int l, const std::int64_t idx[3]) const {
    const double R = static_cast<double>(field.scale(l));
    tessera::Vec3 x;
    for (int a = 0; a < 3; ++a)
      x[a] = origin[a] + h[a] * ((static_cast<double>(idx[a]) + (assoc == tessera::Association::Cell ? 0.5 : 0.0)) / R);
    return x;
  }
  void add(int level, const std::int64_t offset[3], const std::int64_t dims[3], const PositionFn& f) {
    std::vector<double> v(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]));
    std::size_t n = 0;
    for (std::int64_t k = 0; k < dims[2]; ++k)
      for (std::int64_t j = 0; j < dims[1]; ++j)
        for (std::int64_t i = 0; i < dims[0]; ++i) {
          const std::int64_t idx[3] = {offset[0] + i, offset[1] + j, offset[2] + k};
          v[n++] = f(position(level, idx));
        }
    data.push_back(std::move(v));
    tessera::AmrPatch p;
    p.level = level;
    for (int a = 0; a < 3; ++a) p.offset[a] = offset[a];
    patches.push_back(p);
    dims_.push_back({dims[0], dims[1], dims[2]});
  }
  void add(const tessera::AmrBox& b, const PositionFn& f) { add(b.level, b.offset, b.dims, f); }
  /// The field, its patches' views set (call after the last add).
  const tessera::AmrField& finish() {
    for (std::size_t n = 0; n < patches.size(); ++n)
      patches[n].view = tessera::FieldView::contiguous(data[n].data(), tessera::DType::Float64, dims_[n][0],
                                                       dims_[n][1], dims_[n][2]);
    field.patches = patches;
    return field;
  }
  tessera::VolumeGeometry geometry() const { return tessera::VolumeGeometry{origin, h, assoc}; }

 private:
  std::vector<std::array<std::int64_t, 3>> dims_;
};

}  // namespace tessera_test
