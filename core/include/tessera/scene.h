#pragma once
/// SceneDesc: everything one render needs besides the field, as plain values. Built by the
/// config module (from YAML) or by hand; core knows nothing of YAML.
#include <tessera/camera.h>
#include <tessera/integrator.h>
#include <tessera/lights.h>
#include <tessera/tiles.h>
#include <tessera/transfer_function.h>

#include <chrono>
#include <cstdint>
#include <vector>

namespace tessera {

/// What one array element of the field is (docs/data-model.md).
enum class Association : int {
  Vertex = 0,  ///< a value at a grid vertex; the medium fills the vertices' box
  Cell = 1,    ///< a value at a cell centre; the medium fills the cells' whole box
};

/// World placement of the field's elements.
/// - Vertex data, uniform axis a: vertex i at origin[a] + i * spacing[a].
/// - Cell data, uniform axis a: cell i covers [origin[a] + i h, origin[a] + (i + 1) h] (h =
///   spacing[a]), its value at the cell's centre; the medium fills the cells' whole box.
/// - Rectilinear axis a (coords[a] != nullptr): the caller's increasing coordinates, never
///   copied, valid while the render runs: dims[a] vertex positions (vertex data) or
///   dims[a] + 1 cell boundaries (cell data); origin[a] and spacing[a] are then unused.
/// Values are reconstructed trilinearly between vertices (or cell centres), each axis' weight
/// taken in its own coordinates, and clamped to the nearest centre over the outer half cell.
struct VolumeGeometry {
  Vec3 origin{0.0};
  Vec3 spacing{1.0};  ///< each component > 0
  Association association = Association::Vertex;
  const double* coords[3] = {nullptr, nullptr, nullptr};  ///< per axis: nullptr = uniform
};

struct ImageDesc {
  /// Largest width and height, and largest spp, that configs and the CLI accept
  /// (docs/config.md "Limits"): 2^20 samples per pixel is already hours of work per image.
  static constexpr int kMaxEdge = 16384;
  static constexpr int kMaxSpp = 1 << 20;
  int width = 512, height = 512;  ///< in [1, kMaxEdge]
  int spp = 16;                   ///< samples per pixel per render call, in [1, kMaxSpp]
  /// Adaptive sampling, 0 = off: a pixel stops after min(spp, max(8, spp/16)) samples once the
  /// relative standard error of its mean luminance is below this (docs/physics.md).
  double target_error = 0.0;
  /// Denoise the displayed image (PNG) with Intel Open Image Denoise (denoiser.h). In core it
  /// only says that the caller makes its Film with auxiliary buffers (Film(w, h, true)):
  /// render_tiles accumulates the first collision's albedo and normal whenever the film has
  /// them. The RGBA estimate is the same bit for bit with or without.
  bool denoise = false;
};

/// Where render_tiles traces: host threads (TBB) or a CUDA device (cuda_render.h). The
/// caller resolves `device: auto` (interfaces: on the GPU when the field is device memory and
/// the build has CUDA) before it fills RenderOptions; core never guesses.
enum class Device : int { Cpu = 0, Cuda = 1 };

struct RenderOptions {
  std::uint64_t seed = 0;
  std::uint64_t frame = 0;  ///< timestep / frame: part of every random stream
  int tile = 8;             ///< tile edge in pixels; 0 = scanline
  TileOrder order = TileOrder::RowMajor;
  /// Worker threads of prepare() (its passes over the field or mesh) and of render_tiles():
  /// 0 = as many as the caller's TBB arena has (all hardware threads by default).
  int threads = 0;
  /// Wall-clock deadline of the render (steady clock); max() = none. render_tiles checks it
  /// before each tile, before each pixel of a tile and every 64 samples of one pixel,
  /// prepare() every 64 samples of the adaptive preview (never per sample); past it
  /// they stop and throw DeadlineExceeded (render.h).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  Device device = Device::Cpu;  ///< Cuda: render_tiles runs render_tiles_cuda (cuda_render.h)
  int cuda_device = 0;          ///< CUDA device index (Device::Cuda), in [0, cuda_device_count())
  /// A cudaStream_t the field's producer queues work on (Device::Cuda): the render reads the
  /// field after that work; null: the whole device is synchronised first.
  void* cuda_stream = nullptr;
  /// Device bytes the render may allocate (field copy, tables, film sums); 0: no limit but the
  /// device's free memory (Device::Cuda).
  std::uint64_t device_memory_limit = 0;
};

struct SceneDesc {
  VolumeGeometry geometry;
  TransferFunction tf;
  CameraDesc camera;
  std::vector<LightDesc> lights;  ///< area lights of every kind, at most 64 (prepare checks)
  BackgroundDesc background;
  IntegratorDesc integrator;
  ImageDesc image;
  RenderOptions options;
};

/// Axis-aligned world bounds of a field under a geometry: [origin, origin + (dims-1)*spacing].
struct Bounds {
  Vec3 lo{0.0}, hi{0.0};
  Vec3 center() const { return 0.5 * (lo + hi); }
  double radius() const;  ///< bounding-sphere radius, half the diagonal
};

}  // namespace tessera
