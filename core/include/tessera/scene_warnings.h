#pragma once
/// Warnings that explain an empty or odd image: what prepare() knows of the data (its finite
/// range, NaN count, bounds) against the scene (transfer function, camera), plus what the
/// render's statistics show (render_warnings(const RenderStats&), stats.h). One sentence each,
/// no prefix, no newline. A warning never fails a render and never changes the image; callers
/// print or record them (tessera-render on stderr and in --stats, the adapter on rank 0).
#include <tessera/render.h>
#include <tessera/stats.h>

#include <string>
#include <vector>

namespace tessera {

/// Optical depth across the whole volume (density_scale x the largest opacity over the data's
/// values x the bounding-box diagonal) below which a render without a real collision names
/// density_scale as the likely cause.
inline constexpr double kThinVolumeDepth = 0.05;

/// What the scene and the data say before rendering, in this order:
///  - no finite vertex at all;
///  - NaN vertices (their count and fraction: no medium there);
///  - a constant field (finite min == max, its value named);
///  - transfer_function.range disjoint from the data's finite range (both named), or the
///    opacity TF zero over the whole data range (the range overlaps but every value there
///    maps to opacity 0): nothing of the field is visible;
///  - the data's bounds entirely behind the camera, outside its view, or covering less than
///    one pixel (pinhole projection of the eight corners of the bounds; a box the camera is
///    inside or straddles counts as in view).
/// Uses scene.summary() (finite min/max, NaN count: the field prepare() saw, under MPI the
/// assembled global field) and scene.desc(); reads no field value.
std::vector<std::string> scene_warnings(const PreparedScene& scene);

/// scene_warnings(scene), then render_warnings(stats), then, when stats.samples > 0 and
/// stats.real_collisions == 0, "nothing of the field is visible: 0 real collisions in N
/// samples; likely cause: ..." naming the first that applies: the transfer function (range or
/// opacity), the camera (data behind, outside the view or under a pixel), density_scale (optical depth of the whole volume below
/// kThinVolumeDepth), else a list of what to check. `stats` are the render's (summed over
/// ranks and cameras where there are several).
std::vector<std::string> render_warnings(const PreparedScene& scene, const RenderStats& stats);

}  // namespace tessera
