#pragma once
/// tessera::insitu::Adapter: the C++ face of the in situ adapter (docs/insitu.md), in the
/// style of Ascent's open / execute / close. The C API (tessera.h) is a thin wrapper over it.
///
/// Lifetime: open() once, execute() once per simulation step, close() at the end (the
/// destructor closes too). Field memory is described with the C descriptors tessera_field
/// and tessera_grid, read in place, only during execute(), only when a render fires.
///
/// Errors: open/execute/close return a status and never throw, except that with
/// `on_error: abort` in the config a failing execute() throws AdapterError (and so does every
/// later execute()). open() never throws. last_error() holds the message of the last failing
/// call ("" after a call that succeeded). See docs/insitu.md for on_error warn / disable.
///
/// Thread safety: close() (and the destructor) while another thread is inside open, execute
/// or field_unchanged waits for that call to return; calls that arrive during a close, or
/// while another thread's call is inside, are refused (TESSERA_ERROR_CONFIG, nothing done,
/// no AdapterError even with `on_error: abort`; last_error() shows the message to the refused
/// thread only). The accessors (last_error, last_results, last_image) read what the last call
/// left: call them from the thread that made it, not while close() runs elsewhere. With MPI,
/// open, execute and close are collective over the communicator.
#include <tessera/image.h>
#include <tessera/stats.h>
#include <tessera/tessera.h>

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::insitu {

/// What `on_error: abort` throws out of open/execute; status() tells what failed.
class AdapterError : public std::runtime_error {
 public:
  AdapterError(tessera_status status, const std::string& message) : std::runtime_error(message), m_status(status) {}
  tessera_status status() const { return m_status; }

 private:
  tessera_status m_status;
};

/// Options of Adapter::open beyond the config file. Every rank passes the same values.
struct OpenOptions {
  /// Replaces the config's `tessera.output_dir` once the config has loaded and validated:
  /// images, Cinema databases and the effective config (which shows this value) go under it.
  /// Kept as given (a relative directory is relative to the process's working directory);
  /// "" = the config's output_dir.
  std::string output_dir;
  /// The config's YAML text, when it comes from memory rather than a file (the Python
  /// package's dict configs): validated exactly as a file is, with `yaml_path` only the name
  /// error messages print and relative file names inside resolved against the working
  /// directory. "" = read `yaml_path`.
  std::string yaml_text;
};

/// The outcome of one render in the last execute() call (one entry per render that fired).
struct RenderResult {
  std::string name;  ///< the render's name in the config
  std::int64_t step = 0;
  double time = 0.0;
  tessera_status status = TESSERA_OK;  ///< TESSERA_OK or what failed
  std::string error;                   ///< "" when status is TESSERA_OK
  std::vector<std::string> files;      ///< files written (rank 0 only; empty on other ranks)
  double render_seconds = 0.0;         ///< rendering only (all cameras for a Cinema render)
  double samples_per_second = 0.0;     ///< stats.samples / render_seconds
  double prepare_seconds = 0.0;        ///< this rank's tessera::prepare time (all cameras)
  double denoise_seconds = 0.0;        ///< rank 0: image.denoise time (all cameras); 0 when off
  /// The simulation's wall time on this rank since the last execute() in which a render fired:
  /// the time spent outside execute() in between (calls that rendered nothing included), i.e.
  /// the steps the simulation computed for this image. The same for every render of one call;
  /// 0 in the first execute() after open() (nothing to compare with).
  double simulation_seconds = 0.0;
  /// render_seconds / simulation_seconds: the in situ cost of this render relative to the
  /// simulation it watches (26 = rendering took 26x the simulation's time); 0 when
  /// simulation_seconds is 0. Also in the rank-0 log line unless quiet.
  double cost_ratio = 0.0;
  /// Passes this render made over its field's values on this rank (the FieldSummary: macrocell
  /// ranges, NaN count, finite min/max). 0: it reused one made earlier in the same call by
  /// another render, or kept from the last call after field_unchanged(); at most 1 per
  /// macrocell edge otherwise, however many Cinema cameras.
  int field_passes = 0;
  /// A curvilinear or unstructured mesh: the render reused the mesh's lookup structure (an
  /// earlier render's in the same call, or the last call's after mesh_unchanged() or for a
  /// geometry that hashes as the one it was built over) instead of building and checking
  /// every element again.
  bool mesh_layout_reused = false;
  /// Several ranks over such a mesh: only the field's values were exchanged between the ranks,
  /// the geometry read from the last exchange's copy (every rank held that geometry: promised,
  /// found by its hash, or within the call that exchanged it) instead of every rank's whole
  /// domains moving again.
  bool mesh_values_only = false;
  /// Several ranks over the kept structure: each rank summarised a share of the mesh's values
  /// (the majorants' value ranges) and the ranks combined the shares, instead of every rank
  /// summarising the whole mesh (the same summary bit for bit).
  bool mesh_summary_shared = false;
  /// Several ranks over such a mesh: the bytes this rank received in the call's exchange (every
  /// rank's packed domains, or only their values when mesh_values_only); 0 on one rank.
  std::uint64_t mesh_exchange_bytes = 0;
  RenderStats stats;  ///< summed over ranks on rank 0 (and over Cinema cameras)
  /// Where it traced: "cpu" or "cuda:N" (tessera.device, docs/gpu.md). stats.bytes_to_device and
  /// stats.bytes_to_host count the bytes copied between host and device (summed over ranks on
  /// rank 0; this rank's device arrays staged to the host are added to bytes_to_host here):
  /// 0 and 0 for a field read in place on the GPU, but for the film's sums.
  std::string device = "cpu";
  /// Rank 0: what may be wrong with the image although it rendered, one sentence each
  /// (tessera::render_warnings(prepared, stats), scene_warnings.h: transfer-function range
  /// missing the data's values or opacity 0 over them, constant field, NaN vertices, data out
  /// of the camera's view, no real collision with its likely cause, too many discarded
  /// samples, paths ended by a loop guard). Decided on rank 0 alone from the global field's
  /// summary and the stats summed over ranks.
  /// Also logged on rank 0 as "tessera: warning: render 'NAME' at step N: ...", quiet or not.
  /// A warning never changes `status`.
  std::vector<std::string> warnings;

  // The samples a render got, and the render budget (`tessera.budget`; docs/insitu.md,
  // "Controlling the cost")
  /// Samples per pixel this render was given: image.spp without a budget; with one, the
  /// plan every rank rendered with (rank 0's), in [image.min_spp, image.spp], or 0 when the
  /// budget skipped the render. The most a pixel got: target_error may stop pixels earlier.
  int planned_spp = 0;
  /// The samples a pixel got on average: stats.samples / (width x height x views, Cinema
  /// views included). Rank 0 (its stats are summed over ranks); per pixel in the EXR's
  /// `samples` channel (on by default with a budget).
  double actual_spp = 0.0;
  /// tessera.budget, the fraction of the simulation's time rendering may take; 0: no budget.
  double budget = 0.0;
  /// With a budget: the budget could not give this render image.min_spp, so it was not
  /// rendered (status TESSERA_OK, no files, a warning in `warnings` naming the budget).
  bool budget_skipped = false;
  /// With a budget (0 without): the account after this call, in seconds: > 0 time under
  /// budget carried forward, < 0 time over it that later renders pay back. The account that
  /// plans is rank 0's; other ranks show their own measure.
  double budget_balance = 0.0;
  /// With a budget (0 without): the run so far, seconds inside execute() in calls that
  /// rendered / the simulation's seconds, to compare with tessera.budget (the first render
  /// of each entry, which measures its cost, may put it over for a while).
  double budget_ratio = 0.0;
};

class Adapter {
 public:
  Adapter();
  ~Adapter();
  Adapter(const Adapter&) = delete;
  Adapter& operator=(const Adapter&) = delete;
  Adapter(Adapter&&) noexcept;
  Adapter& operator=(Adapter&&) noexcept;

  /// Loads and validates the YAML config (TESSERA_ERROR_CONFIG: the message names
  /// file:line:column and key path), creates output_dir and writes the effective config to
  /// output_dir/tessera_effective_config.yaml (rank 0, atomically; TESSERA_ERROR_IO).
  /// mpi_comm_f: MPI_Comm_c2f(comm), or -1 for no MPI. A second open() closes the first.
  tessera_status open(const std::string& yaml_path, int mpi_comm_f = -1);
  /// As open(yaml_path, mpi_comm_f), with `options` applied to the loaded config (the C API's
  /// tessera_open_with_output_dir).
  tessera_status open(const std::string& yaml_path, int mpi_comm_f, const OpenOptions& options);

  /// Evaluates the triggers for `step` and renders what fires (see tessera_execute). With
  /// final_step and the global option render_final_step, every render fires (the C API's
  /// tessera_execute_final). Returns TESSERA_OK, or the status of the first render that
  /// failed in this call (the others still run unless on_error is abort), or
  /// TESSERA_ERROR_DISABLED when a render that fired is disabled (on_error: disable).
  tessera_status execute(std::int64_t step, double time, const tessera_grid& grid,
                         std::span<const tessera_field> fields, bool final_step = false);

  /// As execute(), for data held as several blocks (domains) per rank, zero included: `mesh`
  /// describes the whole mesh (the same on every rank), `domains` this rank's blocks (the C
  /// API's tessera_execute_domains and, with final_step, tessera_execute_domains_final; see
  /// tessera.h for the checks and their TESSERA_ERROR_DATA). execute() is this call with one
  /// vertex-centred, uniform domain.
  tessera_status execute_domains(std::int64_t step, double time, const tessera_mesh& mesh,
                                 std::span<const tessera_domain> domains, bool final_step = false);

  /// As execute(), for curvilinear and unstructured domains (the C API's
  /// tessera_execute_mesh_domains and, with final_step, tessera_execute_mesh_domains_final;
  /// see tessera.h for the checks and their TESSERA_ERROR_DATA).
  tessera_status execute_mesh_domains(std::int64_t step, double time, std::span<const tessera_mesh_domain> domains,
                                      bool final_step = false);

  /// For language bindings: stands for one execute() (call_kind 0), execute_domains() (1) or
  /// execute_mesh_domains() (2) whose arguments the binding refused on this rank before they
  /// reached the library (the C API's tessera_execute_refused): collective like that call;
  /// a render that fires fails on every rank with TESSERA_ERROR_DATA, this rank's message
  /// being `reason`, the others' naming this rank and quoting it.
  tessera_status execute_refused(std::int64_t step, double time, int call_kind, const std::string& reason,
                                 bool final_step = false);

  /// Whether execute(step, ..., final_step) would evaluate any render: a trigger fires on the
  /// step, a `when` trigger must look at the field, or final_step with render_final_step.
  /// False: that call touches no field memory and returns at once (no MPI communication), so
  /// a binding need not even describe its arrays (the Python package walks a million domains
  /// only when this is true). A function of the config and the arguments alone (false when
  /// not open); the accessors' thread rules apply. Never throws.
  bool fires(std::int64_t step, bool final_step) const noexcept;

  /// The simulation's promise that the values of the field called `field_name` (its
  /// tessera_field name) at the next execute() are bit-for-bit those it had at the last one
  /// (the C API's tessera_field_unchanged). That execute then reuses the field's summary (the
  /// pass over its values behind the majorants and `range: auto`) instead of reading the
  /// values again; RenderResult::field_passes shows 0. One-shot: it applies to the next
  /// execute() only, whether a render fires in it or not; a call without it makes the next
  /// render read the field again. The adapter still compares the field's layout (data
  /// pointer, dtype, dims, strides, ghosts, global placement) and reads the field again when
  /// it differs. With MPI not collective; the summary is reused only if every rank made the
  /// call. The promise is not checked: values that did change give majorants that may be too
  /// low, i.e. a biased image. Returns TESSERA_OK, TESSERA_ERROR_CONFIG when the adapter is
  /// not open, TESSERA_ERROR_DATA when no render of the config can use a field of that name
  /// (last_error() says why). Never throws.
  tessera_status field_unchanged(const std::string& field_name) noexcept;

  /// The promise that the next execute_mesh_domains() passes this rank's domains with the same
  /// geometry as the last one: only field values differ (the C API's tessera_mesh_unchanged,
  /// whose comment says what is reused and how the ranks agree). One-shot. Never throws.
  tessera_status mesh_unchanged() noexcept;

  /// The CUDA stream (a cudaStream_t) on which the simulation computes its device arrays (the
  /// C API's tessera_set_cuda_stream): before reading them Tessera waits for the work queued
  /// on it; null (the default): it synchronises the whole device first. Kept until changed.
  /// execute() returns only when the GPU no longer reads the arrays. Not collective. Returns
  /// TESSERA_OK, or TESSERA_ERROR_CONFIG when the adapter is not open. Never throws.
  tessera_status set_cuda_stream(void* cuda_stream) noexcept;

  /// Releases everything. Idempotent. Waits for a call another thread is making. Returns
  /// TESSERA_OK; with MPI collective, TESSERA_ERROR_CONFIG when a rank was still inside an
  /// execute call that renders instead of closing (last_error() says which; released all the
  /// same, and that rank's call fails too).
  tessera_status close() noexcept;

  bool is_open() const noexcept;
  /// "" after a call that succeeded.
  const std::string& last_error() const noexcept;
  /// One entry per render that fired in the last execute(), in config order; empty when
  /// nothing fired. Valid until the next execute() or close().
  const std::vector<RenderResult>& last_results() const noexcept;
  /// Rank 0: the last image rendered by the render called `name` (for a Cinema render, its
  /// main camera); nullptr if it has not rendered successfully or on other ranks. Valid until
  /// that render renders again, or close().
  const Image* last_image(const std::string& name) const noexcept;
  /// Quiet: no per-render log line (failures are still logged). Default false.
  void set_quiet(bool quiet) noexcept;

 private:
  struct Impl;
  friend struct ::tessera_adapter;  // the C API wraps an Impl
  std::unique_ptr<Impl> m_impl;
};

}  // namespace tessera::insitu
