#pragma once
// Private: one table per enum of the schema (and one for the light kinds), name <-> value. The parsers read them (which
// word means which value, and the allowed words in messages, in table order) and to_yaml
// writes from them, so each name is spelled once. Image formats have their own table with
// extension and writer (core's tessera/image_format.h); dtype names are core's dtype_name.
#include <tessera/config/config.h>

#include <cstddef>
#include <iterator>
#include <string>
#include <variant>
#include <vector>

namespace tessera::config::detail {

/// One word of the schema and the enum value it stands for.
template <class E>
struct EnumName {
  const char* name;
  E value;
};

inline constexpr EnumName<OnError> kOnErrorNames[] = {
    {"warn", OnError::Warn}, {"disable", OnError::Disable}, {"abort", OnError::Abort}};
inline const EnumName<DType> kDTypeNames[] = {{dtype_name(DType::UInt8), DType::UInt8},
                                              {dtype_name(DType::Int16), DType::Int16},
                                              {dtype_name(DType::UInt16), DType::UInt16},
                                              {dtype_name(DType::Float32), DType::Float32},
                                              {dtype_name(DType::Float64), DType::Float64}};
inline constexpr EnumName<Distribution> kDistributionNames[] = {
    {"replicated", Distribution::Replicated}, {"distributed", Distribution::Distributed}, {"auto", Distribution::Auto}};
inline constexpr EnumName<DeviceChoice> kDeviceNames[] = {
    {"auto", DeviceChoice::Auto}, {"cpu", DeviceChoice::Cpu}, {"cuda", DeviceChoice::Cuda}};
inline constexpr EnumName<ByteOrder> kByteOrderNames[] = {{"little", ByteOrder::Little}, {"big", ByteOrder::Big}};
inline constexpr EnumName<Association> kAssociationNames[] = {{"vertex", Association::Vertex},
                                                              {"cell", Association::Cell}};
/// The `type:` word of each light kind, one row per alternative of LightSpec in its order; a
/// row's value is that kind's spec with its defaults, which parse_light fills in.
inline constexpr EnumName<LightSpec> kLightTypeNames[] = {{"rect", RectLightSpec{}}, {"sphere", SphereLightSpec{}}};
static_assert(
    [] {
      std::size_t i = 0;
      for (const auto& row : kLightTypeNames)
        if (row.value.index() != i++) return false;
      return i == std::variant_size_v<LightSpec>;
    }(),
    "kLightTypeNames: one row per alternative of LightSpec, in its order");
/// The `type:` word of the kind `light` holds.
inline const char* light_type_name(const LightSpec& light) { return kLightTypeNames[light.index()].name; }
inline constexpr EnumName<BackgroundType> kBackgroundTypeNames[] = {
    {"constant", BackgroundType::Constant}, {"gradient", BackgroundType::Gradient}, {"envmap", BackgroundType::EnvMap}};
inline constexpr EnumName<Scattering> kScatteringNames[] = {{"single", Scattering::Single},
                                                            {"multiple", Scattering::Multiple}};
inline constexpr EnumName<Shading> kShadingNames[] = {
    {"phase", Shading::Phase}, {"brdf", Shading::Brdf}, {"hybrid", Shading::Hybrid}};
inline constexpr EnumName<FreePath> kFreePathNames[] = {{"delta", FreePath::Delta}, {"raymarch", FreePath::Raymarch}};
inline constexpr EnumName<MajorantMode> kMajorantNames[] = {{"grid", MajorantMode::Grid},
                                                            {"global", MajorantMode::Global}};
inline constexpr EnumName<ShadowMode> kShadowNames[] = {{"ratio", ShadowMode::Ratio}, {"delta", ShadowMode::Delta}};
inline constexpr EnumName<SamplerKind> kSamplerNames[] = {{"independent", SamplerKind::Independent},
                                                          {"sobol", SamplerKind::Sobol}};
inline constexpr EnumName<CameraInterpolation> kCameraInterpolationNames[] = {{"linear", CameraInterpolation::Linear},
                                                                              {"smooth", CameraInterpolation::Smooth}};
inline constexpr EnumName<TileOrder> kTileOrderNames[] = {{"row", TileOrder::RowMajor}, {"morton", TileOrder::Morton}};
inline constexpr EnumName<ToneMap::Curve> kToneMapNames[] = {
    {"aces", ToneMap::Curve::Aces}, {"reinhard", ToneMap::Curve::Reinhard}, {"clamp", ToneMap::Curve::Clamp}};
inline constexpr EnumName<Corner> kCornerNames[] = {{"top-left", Corner::TopLeft},
                                                    {"top-right", Corner::TopRight},
                                                    {"bottom-left", Corner::BottomLeft},
                                                    {"bottom-right", Corner::BottomRight}};
inline constexpr EnumName<BarOrientation> kOrientationNames[] = {{"vertical", BarOrientation::Vertical},
                                                                 {"horizontal", BarOrientation::Horizontal}};

/// The name of `value` in `table`: rows with .name and .value (EnumName, ImageFormatInfo).
/// Every value of an enum has a row; "" would mean a table is missing one.
template <class Table, class E>
const char* name_of(const Table& table, E value) {
  for (const auto& row : table)
    if (row.value == value) return row.name;
  return "";
}

/// The names of `table`, in its order.
template <class Table>
std::vector<std::string> names_of(const Table& table) {
  std::vector<std::string> names;
  for (const auto& row : table) names.emplace_back(row.name);
  return names;
}

}  // namespace tessera::config::detail
