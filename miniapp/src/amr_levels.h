#pragma once
/// tessera-heat --amr: refined levels that follow a moving heat source (docs/miniapp.md,
/// "Refinement levels").
///
/// Level 0 is the solver's grid. Levels 1 .. L-1 (L = 2 or 3) are boxes around the followed
/// source, re-gridded every step: aligned to level 0 (their corners are level-0 vertices, or
/// level-0 cell faces), clipped at the mesh, each inside the level below. Level l+1 refines
/// level l by `ratio` (2 or 4) per axis; R_l = ratio^l.
///
/// What the fine levels hold: every level samples one continuous field,
///   f(x) = I_0[T](x) + sum_s (u_s(x) - I_0[u_s](x)),
/// where T is the solver's temperature on level 0, I_0 is trilinear interpolation between
/// level-0 samples (the renderer's reconstruction, clamped at the outer samples), and u_s is
/// source s's steady temperature excess (heat_sources.h: steady_excess) at the step's time.
/// The second term is the part of the sources' steady profile that level 0 cannot hold: the
/// sub-grid detail of the sources. At level-0 samples f = T exactly, so level 0 and the fine
/// levels agree where they meet; it is an estimate of the fine-scale solution (the quasi-steady
/// profile of a frozen source), not a fine-grid solve.
///
/// Vertex data: level-l vertex i sits at level-0 position i / R_l. Cell data (cells centred on
/// the solver's vertices): level-l cell i has its centre at level-0 position
/// (i + 0.5) / R_l - 0.5. Values are sampled at these points.
///
/// Spread over ranks: a rank holds the elements of each level whose level-0 position lies in
/// its own block (level-l index i with floor(i / R_l) in [offset, offset + owned)), so no rank
/// holds a whole level and every value reads only the rank's array and its ghost layer. Each
/// element's value depends only on its global index and level-0's values, so it is the same
/// for any number of ranks.
#include "cart_decomposition.h"
#include "heat_solver.h"

#include <array>
#include <cstdint>
#include <vector>

namespace heat {

/// A refined box in level-0 units: vertex data: level-0 vertices lo .. hi (hi > lo); cell
/// data: level-0 cells [lo, hi).
struct AmrBox {
  Index3 lo{}, hi{};
};

/// This rank's part of one level: `dims` elements from level-l index `offset`; C order, i
/// fastest, in `values`.
struct AmrPatch {
  int level = 0;
  Index3 offset{}, dims{};
  std::vector<double> values;
};

struct AmrSettings {
  int levels = 2;     ///< 2 or 3
  int ratio = 2;      ///< 2 or 4, the same between every two levels
  bool cell = false;  ///< cell data (cells centred on the solver's vertices), else vertex data
  /// Half-width of level l's box (l = 1, 2) in units of the followed source's sigma.
  std::array<double, 2> half_width_sigmas{3.0, 1.5};
};

/// The boxes of levels 1 .. levels-1 around `centre` (unit-cube position): level l's box spans
/// centre +- half_width[l-1] (rounded outward to level 0), clipped at the mesh of `global`
/// level-0 vertices with spacing h, and to level l-1's box. Every box holds at least one level-0
/// interval (or cell) per axis.
std::vector<AmrBox> refined_boxes(const Index3& global, const std::array<double, 3>& h, bool cell,
                                  const std::array<double, 3>& centre, const std::vector<double>& half_width);

/// The elements of `box` at a level of scale R that a rank with level-0 block
/// [offset, offset + owned) holds: level-l offset and counts (a count <= 0: none).
void rank_share(const AmrBox& box, std::int64_t R, bool cell, const Index3& offset, const Index3& owned,
                Index3& share_offset, Index3& share_dims);

class AmrLevels {
 public:
  /// Throws std::invalid_argument for levels outside 2..3 or a ratio other than 2 or 4.
  AmrLevels(const CartDecomposition& decomp, const HeatParams& params, const AmrSettings& settings,
            HeatSource followed);

  /// Re-grids around the followed source at the solver's time and fills this rank's patches
  /// from the solver's array (its ghost layer must be current: as after step()). Local.
  void update(const HeatSolver& solver);

  /// This rank's non-empty patches of levels 1 .. levels-1 (valid until the next update).
  const std::vector<AmrPatch>& patches() const { return m_patches; }
  /// The boxes of levels 1 .. levels-1 of the last update (the same on every rank).
  const std::vector<AmrBox>& boxes() const { return m_boxes; }
  int levels() const { return m_settings.levels; }
  int ratio() const { return m_settings.ratio; }

 private:
  void fill(const HeatSolver& solver, AmrPatch& patch) const;

  const CartDecomposition& m_decomp;
  HeatParams m_params;
  AmrSettings m_settings;
  HeatSource m_followed;
  std::vector<AmrBox> m_boxes;
  std::vector<AmrPatch> m_patches;
};

}  // namespace heat
