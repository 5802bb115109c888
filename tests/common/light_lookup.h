#pragma once
/// Tests' look-ups into a SceneDesc's light list by kind (the renderer itself never needs
/// them: it walks the variant list once, light_set.h).
#include <tessera/lights.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace tessera {

/// How many lights of kind D `lights` holds.
template <class D>
std::size_t count_lights(const std::vector<LightDesc>& lights) {
  std::size_t n = 0;
  for (const LightDesc& l : lights) n += std::holds_alternative<D>(l) ? 1 : 0;
  return n;
}

/// The n-th light of kind D in `lights` (counted in list order), const or not as `lights`;
/// throws std::out_of_range.
template <class D, class List>
requires std::is_same_v<std::remove_const_t<List>, std::vector<LightDesc>>
auto& nth_light(List& lights, std::size_t n) {
  std::size_t seen = 0;
  for (auto& l : lights)
    if (auto* d = std::get_if<D>(&l); d && seen++ == n) return *d;
  throw std::out_of_range("light " + std::to_string(n) + " of its kind: the list holds " + std::to_string(seen));
}

}  // namespace tessera
