#pragma once
/// The field the MPI benchmarks render (mpi_render_bench, distributed_bench): a heat-like
/// float32 field (warm blobs on 300 K, world size 1) split into k-slabs over the ranks, each
/// rank's slab held as a simulation holds it: C order with one ghost layer per side.
#include "parallel/parallel_context.h"

#include <tessera/field_view.h>
#include <tessera/scene.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tessera::bench {

/// Temperature at vertex (i, j, k) of an n^3 grid: 300 K plus two Gaussian blobs, up to 400 K.
inline double heat_blobs(int n, std::int64_t i, std::int64_t j, std::int64_t k) {
  const double x = i / (n - 1.0), y = j / (n - 1.0), z = k / (n - 1.0);
  const auto blob = [&](double cx, double cy, double cz, double r) {
    return std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz)) / (r * r));
  };
  return 300.0 + 100.0 * std::min(1.0, blob(0.4, 0.45, 0.55, 0.22) + 0.8 * blob(0.65, 0.6, 0.35, 0.15));
}

/// What the MPI benchmarks' scenes of heat_blobs share: the n^3 grid in a unit box, the
/// transfer function's range [300, 400] K, a 40-degree camera with z up, one rect light of
/// `light` above the box, a grey-blue background, 16-pixel tiles. The caller sets the rest
/// (transfer function, camera position and target, image, scattering, threads).
inline SceneDesc heat_blobs_scene(int n, double light) {
  SceneDesc s;
  s.geometry.spacing = Vec3(1.0 / (n - 1));
  s.tf.lo = 300.0;
  s.tf.hi = 400.0;
  s.camera.up = Vec3(0.0, 0.0, 1.0);
  s.camera.fov_deg = 40.0;
  s.lights.push_back(RectLightDesc{Vec3(0.5, 0.5, 3.0), Vec3(0.5, 0.5, 0.5), 1.2, 1.2, Color(light)});
  s.background.color = Color(0.2, 0.2, 0.25);
  s.options.tile = 16;
  return s;
}

/// This rank's slab of the n^3 field: slabs differ by at most one layer (the first n % size
/// ranks get one more). `view` points into `local`; a KSlab is not copied or moved.
struct KSlab {
  std::vector<float> local;
  FieldView view;
  insitu::GlobalPlacement where;

  KSlab(int n_, int rank, int size) {
    const std::int64_t n = n_, base = n / size, extra = n % size;
    const std::int64_t nz = base + (rank < extra ? 1 : 0);
    const std::int64_t z0 = rank * base + std::min<std::int64_t>(rank, extra);
    const std::int64_t full[3] = {n + 2, n + 2, nz + 2};
    local.assign(static_cast<std::size_t>(full[0] * full[1] * full[2]), 0.0f);
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < n; ++j)
        for (std::int64_t i = 0; i < n; ++i)
          local[static_cast<std::size_t>(((k + 1) * full[1] + j + 1) * full[0] + i + 1)] =
              static_cast<float>(heat_blobs(n_, i, j, z0 + k));
    const std::int64_t strides[3] = {4, 4 * full[0], 4 * full[0] * full[1]}, one[3] = {1, 1, 1};
    view = FieldView::with_ghosts(local.data(), DType::Float32, full, strides, one, one);
    where = insitu::GlobalPlacement{{n, n, n}, {0, 0, z0}};
  }
  KSlab(const KSlab&) = delete;
  KSlab& operator=(const KSlab&) = delete;
};

}  // namespace tessera::bench
