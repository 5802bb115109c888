#pragma once
/// The kernel files of the area-light kinds, one per alternative of LightDesc (lights.h).
/// A new kind adds its file here; the static_assert below fails until every alternative of
/// LightDesc has its LightKind.
#include "lights/light_kind.h"
#include "lights/rect_light.h"
#include "lights/sphere_light.h"

#include <type_traits>
#include <variant>

namespace tessera {

namespace detail {
template <class V>
struct AllKindsPrepared;
template <class... D>
struct AllKindsPrepared<std::variant<D...>> {
  static constexpr bool value = (std::is_trivially_copyable_v<typename LightKind<D>::Kernel> && ...);
};
}  // namespace detail
static_assert(detail::AllKindsPrepared<LightDesc>::value,
              "every alternative of LightDesc needs a LightKind with a trivially copyable Kernel");

}  // namespace tessera
