#pragma once
/// The bounds that keep every sampling loop finite (docs/physics.md "Loop guards and scene
/// bounds"). prepare() checks or applies them; the kernels guard each loop with the step
/// budgets and count what they end in RenderStats::stalled_paths.

namespace tessera {

/// Extinction is clamped to this optical thickness per voxel (per smallest spacing): at
/// sigma_t * spacing >= 1000 the transmittance across one voxel, e^-1000, is 0 in double
/// precision (below 4.9e-324) with or without the clamp, and a collision moves by at most
/// ~1e-3 voxel on average; the image is unchanged within noise, the cost per voxel bounded.
inline constexpr double kMaxOpticalThicknessPerVoxel = 1000.0;

/// Delta / ratio tracking steps per traversal (one free flight or one transmittance
/// estimate). The clamp above bounds the expected count by 1000 x the ray's length in
/// voxels (1.8e6 across a 1024^3 box); a traversal over this budget ends its path.
inline constexpr double kMaxTrackingSteps = 16777216.0;  // 2^24

/// Raymarch steps across the data: prepare() refuses integrator.step below
/// (box diagonal in smallest spacings) / kMaxMarchSteps, and a march over the budget (plus
/// two for the jittered start) ends its path.
inline constexpr double kMaxMarchSteps = 1048576.0;  // 2^20

/// Grid spacing, each axis, in world units: squares of every world length (norms, distances,
/// normalisation) stay normal doubles, neither underflowing to 0 nor overflowing to Inf.
inline constexpr double kMinSpacing = 1e-100;
inline constexpr double kMaxSpacing = 1e100;

/// Positions and lengths (volume origin and far corner, camera position / look_at /
/// aperture / focus_distance, light positions, targets and sizes) are refused beyond this
/// many smallest spacings in magnitude: there a double still resolves 2^-12 voxel.
inline constexpr double kMaxCoordinateVoxels = 1099511627776.0;  // 2^40

/// Light radiance (color * intensity, each channel) and a constant or gradient background's
/// (color * intensity) at most 1e30: pixel values stay far below float32's 3.4e38, so the
/// EXR never holds an Inf that the double film did not.
inline constexpr double kMaxRadiance = 1e30;

}  // namespace tessera
