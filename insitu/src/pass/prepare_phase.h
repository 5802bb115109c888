#pragma once
/// The scene and prepare phases: the scene the render's config describes over the bound field
/// (camera, lights, envmap, transfer function over its range, the Cinema views), then
/// prepare() over the field as placed (replica, hierarchy or paged; the majorants from the
/// field's summary, kept for the next prepare of the field when this one had to make it).
#include "outputs/cinema.h"
#include "pass/placement_phase.h"

#include <tessera/adapter.h>
#include <tessera/render.h>
#include <tessera/scene.h>

#include <optional>
#include <utility>
#include <vector>

namespace tessera::insitu {

/// What the render draws: its scene and, with output.cinema, the Cinema cameras.
struct SceneSetup {
  SceneDesc scene;
  std::vector<CinemaView> views;
};

/// The scene phase: `range` is the field's range (0, 0 when not needed). Nothing when the
/// ranks agreed on a failure.
std::optional<SceneSetup> scene_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                      std::pair<double, double> range);

/// prepare() of `scene` (its options' deadline set) over the placed field, collective in
/// distributed mode; throws (a passed time limit included). Adds to result.prepare_seconds
/// and, when it built a summary, to result.field_passes.
PreparedScene prepare_scene(const PassContext& pass, const BoundField& field, PlacedField& placed,
                            const SceneDesc& scene, RenderResult& result);

/// The prepare phase: prepare_scene behind the gate. Nothing when the ranks agreed on a failure.
std::optional<PreparedScene> prepare_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field,
                                           PlacedField& placed, const SceneDesc& scene, RenderResult& result);

}  // namespace tessera::insitu
