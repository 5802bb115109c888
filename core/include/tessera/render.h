#pragma once
/// The renderer: prepare once per frame, then render all tiles or a chosen subset.
///
/// prepare() validates the scene against the field (throws std::invalid_argument naming the
/// fault), builds the majorant grid, light and environment sampling tables and the tile list.
/// The PreparedScene references the field memory, which must outlive it. render_tiles() is
/// thread-safe, allocates nothing per sample, throws nothing from inside the loop.
#include <tessera/field_view.h>
#include <tessera/film.h>
#include <tessera/scene.h>
#include <tessera/stats.h>

#include <functional>
#include <memory>
#include <span>

namespace tessera {

struct PreparedSceneImpl;

class PreparedScene {
 public:
  PreparedScene();
  ~PreparedScene();
  PreparedScene(PreparedScene&&) noexcept;
  PreparedScene& operator=(PreparedScene&&) noexcept;

  const SceneDesc& desc() const;
  const std::vector<Tile>& tiles() const;
  Bounds bounds() const;
  const PreparedSceneImpl& impl() const { return *m_impl; }

 private:
  friend PreparedScene prepare(const FieldView&, const SceneDesc&);
  std::unique_ptr<PreparedSceneImpl> m_impl;
};

Bounds field_bounds(const FieldView& field, const VolumeGeometry& g);

/// Min and max of the finite vertex values (NaN and Inf ignored); {0,0} if none is finite.
std::pair<double, double> field_range(const FieldView& field);

PreparedScene prepare(const FieldView& field, const SceneDesc& scene);

/// Render the tiles with the given indices into `film` (which must be width x height), with
/// TBB over tiles. Adds spp samples to each pixel, continuing each pixel's sample indices.
/// `progress`, if set, is called from worker threads with the number of tiles finished.
void render_tiles(const PreparedScene& scene, std::span<const int> tile_indices, Film& film,
                  RenderStats& stats, const std::function<void(int)>& progress = {});

/// Render every tile.
void render(const PreparedScene& scene, Film& film, RenderStats& stats,
            const std::function<void(int)>& progress = {});

}  // namespace tessera
