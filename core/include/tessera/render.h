#pragma once
/// The renderer: prepare once per frame, then render all tiles or a chosen subset.
///
/// prepare() validates the scene against the field (throws std::invalid_argument naming the
/// fault), builds the majorant grid, light and environment sampling tables and the tile list.
/// The PreparedScene references the field memory, which must outlive it. render_tiles() is
/// thread-safe, allocates nothing per sample, throws nothing from inside the loop. Both run
/// on at most options.threads threads (their own task arena when the caller's is of another
/// width), whatever arena the caller is in.
///
/// The one pass over the field's values that prepare() needs (the FieldSummary: macrocell
/// value ranges, NaN count, finite min/max) can be carried from one prepare to the next of
/// the same, unchanged field: prepare(field, scene, reuse) and PreparedScene::summary().
#include <tessera/amr.h>
#include <tessera/brick_cache.h>
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/film.h>
#include <tessera/magnitude_field.h>
#include <tessera/mesh.h>
#include <tessera/scene.h>
#include <tessera/stats.h>

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <utility>

namespace tessera {

struct PreparedSceneImpl;
class MeshLayout;  // mesh/mesh_layout.h: what a mesh's prepare builds from its geometry

class PreparedScene {
 public:
  PreparedScene();
  ~PreparedScene();
  PreparedScene(PreparedScene&&) noexcept;
  PreparedScene& operator=(PreparedScene&&) noexcept;

  const SceneDesc& desc() const;
  const std::vector<Tile>& tiles() const;
  Bounds bounds() const;
  /// The field summary the majorants were derived from (never null once prepared): pass it
  /// to the next prepare of the same, unchanged field to skip the pass over the values.
  const std::shared_ptr<const FieldSummary>& summary() const;
  /// True iff prepare() reused the summary it was given instead of scanning the field.
  bool summary_reused() const;
  /// A mesh scene (prepare(const Mesh&, ...)): its layout, for the next prepare of the same
  /// mesh; null for other fields. Whether this prepare reused the one it was given.
  const std::shared_ptr<const MeshLayout>& mesh_layout() const;
  bool mesh_layout_reused() const;

 private:
  friend PreparedScene prepare(const FieldView&, const SceneDesc&, std::shared_ptr<const FieldSummary>);
  friend PreparedScene prepare(const PagedField&, const SceneDesc&, std::shared_ptr<const FieldSummary>);
  friend PreparedScene prepare(const AmrField&, const SceneDesc&, std::shared_ptr<const FieldSummary>);
  friend PreparedScene prepare(const Mesh&, const SceneDesc&, std::shared_ptr<const MeshLayout>, const MeshChecked&);
  friend PreparedScene prepare(const Mesh&, const SceneDesc&, std::shared_ptr<const MeshLayout>, const MeshChecked&,
                               std::shared_ptr<const FieldSummary>);
  friend PreparedScene prepare(const MagnitudeField&, const SceneDesc&, std::shared_ptr<const FieldSummary>);
  /// The prepared data, for core's own sources (core/src/scene/prepared_scene_impl.h).
  friend const PreparedSceneImpl& prepared_scene_impl(const PreparedScene& scene);
  std::unique_ptr<PreparedSceneImpl> m_impl;
};

/// Thrown by render_tiles (and by prepare's adaptive preview) once options.deadline has
/// passed: every thread stops before its next tile or its next pass over a tile, the film
/// holds a partial image and must be discarded. tiles_done() of tiles_total() tiles of the
/// call were finished (0 of the scene's tiles when thrown by prepare).
class DeadlineExceeded : public std::runtime_error {
 public:
  DeadlineExceeded(std::size_t tiles_done, std::size_t tiles_total);
  std::size_t tiles_done() const { return m_done; }
  std::size_t tiles_total() const { return m_total; }

 private:
  std::size_t m_done, m_total;
};

Bounds field_bounds(const FieldView& field, const VolumeGeometry& g);

/// Min and max of the finite vertex values (NaN and Inf ignored); nullopt if none is finite
/// (distinct from a field that is all zero, {0, 0}).
std::optional<std::pair<double, double>> field_range(const FieldView& field);

PreparedScene prepare(const FieldView& field, const SceneDesc& scene);

/// As prepare(field, scene), reusing `reuse` instead of scanning the field when it matches:
/// reuse->matches(field, majorant_edge(field, scene.integrator)), i.e. it was built from the
/// same data pointer, dtype, dims and byte strides with the macrocell edge this scene needs.
/// Otherwise (null, another layout or another edge) a fresh summary is built, exactly as
/// prepare(field, scene) does; the result's summary() / summary_reused() tell which.
///
/// Contract: passing a matching summary is the caller's guarantee that the values at that
/// memory are the ones it was built from. prepare cannot check this (it would take the very
/// pass it saves); with changed values the majorants may be too low and the image biased.
/// The image is bit-identical to that of prepare(field, scene) when the guarantee holds.
PreparedScene prepare(const FieldView& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> reuse);

/// Distributed mode (brick_cache.h): prepares the scene over a field that this rank holds only
/// a block of. `summary` (non-null) must be the whole field's summary with the edge
/// majorant_edge() gives for the global dims (FieldSummary::from_parts of every rank's
/// partial). Validation, bounds, majorants, tiles and culling are exactly those of
/// prepare() over the whole field; the kernels read vertices through field.cache, so
/// render_tiles() must run while a service thread serves that cache. Images are bit-identical
/// to those of prepare() over the whole field.
///
/// Adaptive sampling (image.target_error > 0): prepare's preview renders pilot samples, i.e.
/// reads the field through the cache too (bracketed like tiles), so the service thread must
/// already be serving the cache when prepare is called. Without adaptive sampling prepare
/// reads no vertex.
///
/// Throws std::invalid_argument (naming the fault) for: a null cache or summary, a cache whose
/// grid has other dims or another dtype, an own block (local.data non-null) that is invalid,
/// of another dtype or not inside the global dims at `offset`, a summary whose edge is not
/// majorant_edge() of the global dims (both edges named) or whose cells do not fit the dims,
/// and every scene fault prepare(FieldView) names. The prepared scene's field descriptor has
/// the global dims and dtype and no data: field_range() must not be called on it.
///
/// A render whose cache fails (BrickCache::fail) does not hang: blocked workers read zeros
/// and render_tiles returns normally; the caller must check field.cache->failed() and
/// discard the film.
PreparedScene prepare(const PagedField& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> summary);

/// Refinement levels (amr.h): prepares the scene over a hierarchy whose patches are all
/// readable here (replicated: the caller's own arrays and a replica of the others').
/// scene.geometry places level 0 (origin, spacing, association); rectilinear axes are not
/// supported with levels yet (std::invalid_argument). `summary`: amr_summary() of this
/// hierarchy at majorant_edge() of level 0, reused as it is (the caller's promise that the
/// values are unchanged), or null to build it. Checks the hierarchy (check_amr) and the scene
/// as prepare(FieldView) does; builds the level tables (amr_table_bytes()). Validation,
/// bounds, warnings, majorants, tiles and culling are those of a field of level 0's dims.
/// The image does not depend on how the levels are cut into patches, nor on their order.
PreparedScene prepare(const AmrField& field, const SceneDesc& scene, std::shared_ptr<const FieldSummary> summary);

/// A curvilinear or unstructured mesh (mesh.h), read in place: check_mesh(mesh) (throws
/// std::invalid_argument naming the domain and element), then the mesh's tables: its layout
/// (canonical element order, location cells: mesh/mesh_layout.h, O(n log n)) and each
/// element's value range, over a uniform vertex grid laid over the mesh's box whose
/// macrocells carry the elements' value ranges as majorants. scene.geometry is not used (the
/// mesh places itself): desc().geometry and bounds() are that grid's. Outside every element
/// the medium is empty. Validation of the rest of the scene, lights, tiles and culling are
/// prepare(FieldView)'s. The image does not depend on how the cells are cut into domains, on
/// their order, nor on the thread count.
///
/// `reuse`: the mesh_layout() of an earlier prepare of the same mesh. When it fits (the same
/// domains with the same counts and shapes: MeshLayout::fits), only check_mesh_indices runs
/// (indices in range and finite vertices, not the shapes) and the layout is shared, not built:
/// the caller's promise that the coordinates, connectivity and ghost masks are bit for bit
/// those it was built from (not checked: that is the pass it saves; a broken promise gives
/// wrong lookups, never a read outside the arrays' counts). The
/// image is then bit-identical to a prepare without `reuse`. When it does not fit, as without.
///
/// `checked`: the receipt of a check the caller ran on these arrays in the same step
/// (MeshChecked, mesh.h). When it covers `mesh` (with its shapes, where no layout is reused)
/// that check is not run again; its value totals, when it has them (a device mesh's), are not
/// measured again. Otherwise prepare checks as described above.
PreparedScene prepare(const Mesh& mesh, const SceneDesc& scene, std::shared_ptr<const MeshLayout> reuse = nullptr,
                      const MeshChecked& checked = {});

/// True when `layout` (a mesh_layout()) fits `mesh`: the same domains with the same counts and
/// shapes, so that prepare(mesh, scene, layout) reuses it. Reads no array.
bool mesh_layout_fits(const MeshLayout& layout, const Mesh& mesh);

/// Ranks that each hold the same mesh (every rank the whole mesh) can share the pass over its
/// values that prepare(mesh, scene, layout) makes: rank r of n summarises share r of n (the
/// elements among a 1/n run of the input's cells, and a 1/n run of the values), the ranks
/// combine the parts (FieldSummary::Parts' reductions: MPI_MIN, MPI_MAX, MPI_BOR, MPI_SUM),
/// mesh_summary_of_parts makes the summary, and prepare(mesh, scene, layout, checked, summary)
/// uses it: the same image bit for bit, whatever n. `layout` must fit `mesh` (the caller's
/// promise that it is the geometry's, as for prepare's reuse) and `checked` must cover its
/// indices (a receipt of check_mesh_indices or more of these arrays: the share reads the
/// values through the connectivity); a layout element that is a ghost now is refused as
/// prepare refuses it. Host memory only (not Mesh::device). Throws std::invalid_argument.
FieldSummary::Parts mesh_summary_parts(const Mesh& mesh, const SceneDesc& scene,
                                       const std::shared_ptr<const MeshLayout>& layout, const MeshChecked& checked,
                                       int share, int shares);
/// The macrocells a share's parts hold for `scene` over `layout` (what combining them moves:
/// 17 bytes each), to weigh against the share's savings (a pass over 1/n of the mesh).
std::uint64_t mesh_summary_cells(const MeshLayout& layout, const SceneDesc& scene);
/// The summary of every share's parts combined, for prepare(mesh, scene, layout, checked, it).
std::shared_ptr<const FieldSummary> mesh_summary_of_parts(FieldSummary::Parts&& parts, const Mesh& mesh,
                                                          const SceneDesc& scene,
                                                          const std::shared_ptr<const MeshLayout>& layout);
/// prepare(mesh, scene, reuse, checked) with `summary` (mesh_summary_of_parts over `reuse`)
/// instead of the pass over the values: `reuse` must fit `mesh`, and the summary be of this
/// scene's macrocell edge and grid (else std::invalid_argument, by name).
PreparedScene prepare(const Mesh& mesh, const SceneDesc& scene, std::shared_ptr<const MeshLayout> reuse,
                      const MeshChecked& checked, std::shared_ptr<const FieldSummary> summary);

/// A vector's magnitude (magnitude_field.h), read in place: each lookup reads the three
/// components and takes magnitude() of them, so the image is bit-identical to prepare() of a
/// float64 array holding the magnitudes. `summary`: magnitude_summary() of this field with
/// majorant_edge() of its components, used as it is (the caller's promise that the values are
/// unchanged), or null to build it (one pass). Throws std::invalid_argument as
/// prepare(FieldView) does, and for components that are invalid or of different dims (named),
/// or a summary of another edge or cell count.
PreparedScene prepare(const MagnitudeField& field, const SceneDesc& scene,
                      std::shared_ptr<const FieldSummary> summary = nullptr);

/// Render the tiles with the given indices into `film` (which must be width x height), with
/// TBB over tiles. Adds spp samples to each pixel, continuing each pixel's sample indices.
/// With adaptive sampling (image.target_error > 0) a pixel gets between the pilot and spp
/// samples and its sample indices start at 0 in every call (so the decision is the same however
/// the tiles are split across calls or ranks): accumulate several adaptive calls into one film
/// only with a different options.frame each (docs/physics.md section 11).
/// When the film has auxiliary sums (Film(w, h, true), for image.denoise) each kept sample's
/// first-collision albedo and normal are added beside its colour, in the same order; the
/// colour sums are the same bit for bit either way.
/// `progress`, if set, is called from worker threads with the number of tiles finished.
/// Past scene.desc().options.deadline the remaining tiles are skipped and DeadlineExceeded
/// is thrown after the workers have stopped (stats then count the work done).
/// With options.device Device::Cuda the tiles are rendered on that GPU (render_tiles_cuda,
/// cuda_render.h: the same estimator and random streams; images equal the CPU's within Monte
/// Carlo error, not bit for bit), its errors thrown as render_tiles_cuda throws them; stats
/// then count the bytes copied between host and device.
void render_tiles(const PreparedScene& scene, std::span<const int> tile_indices, Film& film, RenderStats& stats,
                  const std::function<void(int)>& progress = {});

/// Render every tile.
void render(const PreparedScene& scene, Film& film, RenderStats& stats, const std::function<void(int)>& progress = {});

}  // namespace tessera
