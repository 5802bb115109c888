#include "shell_geometry.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace heat {

void ShellGeometry::validate() const {
  if (n_r < 3 || n_z < 3 || n_theta < 3)
    throw std::invalid_argument("the shell needs at least 3 vertices along each axis, got " + std::to_string(n_r) +
                                " x " + std::to_string(n_theta) + " x " + std::to_string(n_z));
  if (!(r0 > 0.0) || !(r1 > r0) || !(height > 0.0) || !std::isfinite(r1) || !std::isfinite(height))
    throw std::invalid_argument("the shell needs 0 < r0 < r1 and height > 0 (finite)");
}

double ShellGeometry::dtheta() const { return 2.0 * std::numbers::pi / static_cast<double>(n_theta); }

double ShellGeometry::theta(std::int64_t j) const {
  const std::int64_t wrapped = ((j % n_theta) + n_theta) % n_theta;
  return static_cast<double>(wrapped) * dtheta();
}

std::array<double, 3> ShellGeometry::position(std::int64_t i, std::int64_t j, std::int64_t k) const {
  const double r = radius(i), t = theta(j);
  return {r * std::cos(t), r * std::sin(t), z(k)};
}

ShellCoordinates shell_block_coordinates(const ShellGeometry& g, std::int64_t first, std::int64_t count) {
  ShellCoordinates c;
  const std::size_t n = static_cast<std::size_t>(g.n_z * g.n_r * count);
  c.x.reserve(n);
  c.y.reserve(n);
  c.z.reserve(n);
  for (std::int64_t j = first; j < first + count; ++j)
    for (std::int64_t i = 0; i < g.n_r; ++i)
      for (std::int64_t k = 0; k < g.n_z; ++k) {
        const std::array<double, 3> p = g.position(i, j, k);
        c.x.push_back(p[0]);
        c.y.push_back(p[1]);
        c.z.push_back(p[2]);
      }
  return c;
}

}  // namespace heat
