#pragma once
/// Named colormaps for colour transfer functions (`diffuse: viridis`).
///
/// Tables hold 17 points at u = i/16 in *linear* RGB: the published (sRGB-encoded) colours
/// converted with the sRGB EOTF, so that an image written with the sRGB transfer shows the
/// colormap's colours. A name ending in `_r` is the reversed map (`viridis_r`).
#include <tessera/config/transfer_function_spec.h>

#include <optional>
#include <string>
#include <vector>

namespace tessera::config {

/// The base names: viridis magma inferno plasma cividis turbo coolwarm grayscale hot.
const std::vector<std::string>& colormap_names();

/// The points of a colormap, or nullopt for an unknown name.
std::optional<std::vector<ColorPoint>> find_colormap(const std::string& name);

/// As find_colormap; throws std::invalid_argument listing the names for an unknown one.
std::vector<ColorPoint> colormap(const std::string& name);

}  // namespace tessera::config
