#pragma once
/// Refinement levels (AMR): a hierarchy of levels, each a set of non-overlapping patches, read
/// in place (the caller's arrays, or a node's replica of other ranks' patches), never
/// resampled or re-bricked.
///
/// Index spaces. Level 0 has dims[a] elements per axis (vertices or cells, association as in
/// VolumeGeometry). Level l+1 splits each level-l cell (or vertex interval) into ratio[l]
/// parts per axis; R_l = ratio[0] * ... * ratio[l-1] (R_0 = 1). Level l has
///   vertex data: (dims[a] - 1) R_l + 1 vertices, vertex i at level-0 index i / R_l;
///   cell data:   dims[a] R_l cells, cell i covering level-0 cells [i / R_l, (i + 1) / R_l).
/// A patch holds the real elements [offset, offset + view.dims) of its level.
///
/// Which level a point takes (the coarse-fine rule, docs/physics.md "Refinement levels"):
/// the finest level whose whole trilinear stencil (its 8 samples, as a uniform field of that
/// level would use them, clamped to the level's extent like any field) lies in real elements
/// of that level's patches; level 0 covers the mesh, so every point has one. Patches of one
/// level are one field: a stencil may take its samples from several patches, so the value
/// never depends on how a level is cut into patches or spread over ranks. Ghost layers are
/// never read. A field linear in x, y, z has the same value at every level (trilinear
/// interpolation reproduces it, and a cell average of a linear function is its centre value).
#include <tessera/brick_cache.h>
#include <tessera/field_summary.h>
#include <tessera/field_view.h>
#include <tessera/scene.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace tessera {

/// Most levels a hierarchy may have (levels 0 .. kMaxAmrLevels - 1).
inline constexpr int kMaxAmrLevels = 8;

/// One patch: its level, the index (at its level) of its first real element, and the view of
/// its real elements (ghosts already skipped; validated, the hierarchy's dtype).
struct AmrPatch {
  int level = 0;
  std::int64_t offset[3] = {0, 0, 0};
  FieldView view;
};

/// Distributed mode: the grid through which a rank reads the patches other ranks hold. Each
/// level's patches' bounding box is placed in one virtual grid, side by side along x (each at a
/// multiple of the brick edge); sample s of level l (inside that box) is virtual element
/// base[l] + s. The virtual grid's bricks (brick_cache.h) are fetched from the patches'
/// owners; elements no patch holds are never read.
struct AmrVirtualLayout {
  std::int64_t dims[3] = {1, 1, 1};
  std::int64_t base[8][3] = {};
};

/// A hierarchy as prepare() takes it. The patches are borrowed: their memory must stay valid
/// and unchanged while a scene prepared from them lives.
struct AmrField {
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};   ///< level-0 elements per axis (>= 1)
  int nlevels = 1;                    ///< 1 .. kMaxAmrLevels
  int ratio[kMaxAmrLevels - 1] = {};  ///< ratio[l]: level l -> l+1, each 2 or 4
  std::span<const AmrPatch> patches;  ///< every patch of every level, any order
  /// Names the patch in messages (the caller's rank and domain); empty: "patch N".
  std::vector<std::string> names;
  /// Distributed mode: the patches this rank does not hold have view.data null (dims and
  /// dtype set) and are read through `cache`, whose grid is `layout.dims` of the dtype; null:
  /// every patch is readable here.
  BrickCache* cache = nullptr;
  AmrVirtualLayout layout;

  /// Elements of level l along axis a (see the file comment); association as the geometry's.
  std::int64_t level_dims(int l, int a, Association assoc) const;
  /// R_l: level-0 cells per level-l cell along an axis is 1 / R_l.
  std::int64_t scale(int l) const;
};

/// A patch's box alone (what ranks tell each other): level, offset and real element counts.
struct AmrBox {
  int level = 0;
  std::int64_t offset[3] = {0, 0, 0};
  std::int64_t dims[3] = {0, 0, 0};
};

/// check_amr on boxes alone (the views are not looked at; `meta.patches` is ignored): for
/// callers that know every rank's boxes but only their own arrays. `name(n)` names box n in
/// messages ("rank 1 domain 4"). Same checks and cost as check_amr.
void check_amr_boxes(const AmrField& meta, Association assoc, std::span<const AmrBox> boxes,
                     const std::function<std::string(std::size_t)>& name);

/// The virtual grid of distributed mode for these boxes (every rank's patches) with bricks of
/// 2^brick_shift elements. Throws std::invalid_argument when it would exceed 2^40 elements
/// along an axis.
AmrVirtualLayout amr_virtual_layout(const AmrField& meta, Association assoc, std::span<const AmrBox> boxes,
                                    int brick_shift);

/// The hierarchy's structural checks, in O(N log N + N_l N_{l+1} / bins) for N patches:
/// nlevels in [1, kMaxAmrLevels]; ratios 2 or 4; every patch's view valid, of the dtype, at a
/// level in [0, nlevels), inside its level's extent; no two patches of one level overlap;
/// level 0 covers the mesh (its element counts add up); every patch of level l+1 lies inside
/// the region level l's patches cover (coarsened outward to level l). Throws
/// std::invalid_argument naming the patch (AmrField::names), level and axis.
void check_amr(const AmrField& field, Association assoc);

/// Bytes prepare() allocates for the hierarchy's lookup tables (level tables, candidate
/// lists, the per-macrocell level table) at macrocell edge `edge`, for memory plans. Cheap
/// (no pass over values).
std::uint64_t amr_table_bytes(const AmrField& field, Association assoc, int edge);

/// The FieldSummary (macrocell value ranges, NaN count, finite range) of the hierarchy at
/// level-0 macrocell edge `edge`: each macrocell's range covers every sample of every level
/// that a point of the macrocell can interpolate from, so majorants derived from it are
/// conservative. Bit-identical for any cut of the same levels into patches.
std::shared_ptr<const FieldSummary> amr_summary(const AmrField& field, Association assoc, int edge);

/// The summary's parts from the patches this rank holds (view.data non-null) only: combining
/// every rank's parts (FieldSummary::Parts: min, max, or, sum) and FieldSummary::from_parts
/// give amr_summary() of the whole hierarchy, bit for bit. The hierarchy must be checked.
FieldSummary::Parts amr_summary_parts(const AmrField& field, Association assoc, int edge);

}  // namespace tessera
