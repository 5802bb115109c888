#pragma once
/// CudaHeatSolver: HeatSolver (heat_solver.h) on one GPU. The temperature field lives in
/// device memory only: the stencil, the heat sources and the walls run as one kernel per step,
/// the halo exchange moves only the faces through the host (CudaHaloExchange), and data() is a
/// device pointer that the adapter reads in place.
///
/// The same equation, scheme, sources (source_stamp, computed on the host by the same code),
/// walls, ghost layout and order of operations as HeatSolver, in double precision, compiled
/// without fused multiply-adds (--fmad=false): the only difference from the CPU field is
/// the device's exp() in the source term (within an ulp or two), so after N steps the two
/// fields agree to rounding (tests/miniapp_gpu/test_heat_solver_cuda.cpp).
///
/// Construct after select_cuda_device (cuda_device.h): the solver uses the calling thread's
/// current device, and a stream of its own.
#include "cart_decomposition.h"
#include "halo_exchange_cuda.h"
#include "heat_simulation.h"
#include "heat_solver.h"

#include <memory>
#include <vector>

struct CUstream_st;  // cudaStream_t

namespace heat {

class CudaHeatSolver final : public HeatSimulation {
 public:
  /// Most heat sources a step can add (the kernel takes them by value).
  static constexpr int kMaxSources = 16;

  /// Throws std::invalid_argument as HeatSolver does (and for more than kMaxSources sources),
  /// std::runtime_error naming the CUDA call for a CUDA failure. Collective: the ranks agree on
  /// a failure of the device allocations before the initial halo exchange.
  CudaHeatSolver(const CartDecomposition& decomp, const HeatParams& params);
  ~CudaHeatSolver() override;
  CudaHeatSolver(const CudaHeatSolver&) = delete;
  CudaHeatSolver& operator=(const CudaHeatSolver&) = delete;

  double stable_dt() const override { return m_stable_dt; }
  void step(double dt) override;
  double time() const override { return m_time; }
  std::int64_t steps() const override { return m_steps; }
  const std::array<double, 3>& spacing() const override { return m_h; }

  /// Device memory: the current step's array, ghosts included.
  const double* data() const override { return m_T; }
  FieldMemory memory() const override { return FieldMemory::device; }
  const Index3& array_dims() const override { return m_dims; }

  /// Reduced on the device; two doubles per block come back.
  std::pair<double, double> local_range() const override;
  /// Copies the array to the host (for --dump and tests, never during a run).
  std::vector<double> owned_values() const override;
  /// The whole local array, ghosts included, copied to the host (tests).
  std::vector<double> array_values() const;

  /// The stream the solver's kernels and copies run on (a cudaStream_t); idle when step()
  /// returns.
  void* cuda_stream() const override { return m_stream; }
  /// The device the solver's arrays are on.
  int device() const { return m_device; }

 private:
  void release() noexcept;

  const CartDecomposition& m_decomp;
  HeatParams m_params;
  Index3 m_dims{};  ///< local array extent, ghosts included
  std::array<double, 3> m_h{};
  double m_stable_dt = 0.0;
  double m_time = 0.0;
  std::int64_t m_steps = 0;
  int m_device = -1;
  CUstream_st* m_stream = nullptr;
  double* m_T = nullptr;      ///< device: this step
  double* m_next = nullptr;   ///< device: the step being computed
  double* m_range = nullptr;  ///< device: per-block min and max of local_range()
  std::unique_ptr<CudaHaloExchange> m_halo;
};

}  // namespace heat
