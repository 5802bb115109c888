#pragma once
/// HeatSimulation: what tessera-heat's loop needs of a heat solver, whichever memory holds the
/// temperature field: HeatSolver (host memory, heat_solver.h) or CudaHeatSolver (one GPU's
/// memory, heat_solver_cuda.h). The choice is made once at setup (--device); a run makes one
/// virtual call per step and per publish, none per vertex.
///
/// Both solve the same equation with the same scheme, sources, walls and ghost layout: the
/// local array is (owned[0]+2) x (owned[1]+2) x (owned[2]+2) doubles, C order with i fastest,
/// one ghost layer per side filled from the neighbouring ranks after every step.
#include "cart_decomposition.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace heat {

/// Where data() points.
enum class FieldMemory { host, device };

class HeatSimulation {
 public:
  virtual ~HeatSimulation() = default;

  /// safety times the stability limit of the explicit scheme.
  virtual double stable_dt() const = 0;
  /// Advances by dt (<= the stability limit; throws otherwise). Collective (halo exchange).
  /// On return the array behind data() holds the new step, ghosts included, and no device work
  /// on it is pending.
  virtual void step(double dt) = 0;

  virtual double time() const = 0;
  virtual std::int64_t steps() const = 0;
  virtual const std::array<double, 3>& spacing() const = 0;

  /// The local array, ghosts included: array_dims() doubles, i fastest, in memory(): a host
  /// pointer, or a device pointer of the GPU the solver runs on. Valid until the next step().
  virtual const double* data() const = 0;
  virtual FieldMemory memory() const = 0;
  virtual const Index3& array_dims() const = 0;
  /// The CUDA stream (a cudaStream_t) the solver computes data() on; null for a host solver.
  virtual void* cuda_stream() const { return nullptr; }

  /// Min and max over this rank's owned vertices.
  virtual std::pair<double, double> local_range() const = 0;
  /// This rank's owned vertices (no ghosts), i fastest, as a host copy (--dump, tests).
  virtual std::vector<double> owned_values() const = 0;
};

/// One heat source's contribution to one step on this rank's block, computed on the host by
/// the same code for both solvers: every owned interior vertex (i, j, k) in [lo, hi] (local
/// indices, inclusive; empty when some lo > hi) gains
///   amp * exp(-|x - centre|^2 * inv_2s2),  x = (offset + (i, j, k)) * h.
/// Plain arrays: the CUDA kernel takes it by value.
struct SourceStamp {
  double centre[3];
  double amp;      ///< dt * the source's amplitude at the step's start time
  double inv_2s2;  ///< 1 / (2 sigma^2)
  std::int64_t lo[3], hi[3];
};

}  // namespace heat
