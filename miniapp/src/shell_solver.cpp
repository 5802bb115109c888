#include "shell_solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace heat {

ShellParams shell_demo_params(const ShellGeometry& geometry) {
  ShellParams p;
  p.geometry = geometry;
  p.inner_value = 330.0;
  const double mid = 0.5 * (geometry.r0 + geometry.r1), h = geometry.height;
  p.sources.resize(2);
  p.sources[0] = {{0.0, 0.0, 0.65 * h}, mid, 4.0, 0.0, 900.0, 0.3, 0.5, 0.08};
  p.sources[1] = {{0.0, 0.0, 0.35 * h}, mid, -4.0, std::numbers::pi, 900.0, 0.3, 0.7, 0.08};
  return p;
}

ShellSolver::ShellSolver(const RingDecomposition& ring, const ShellParams& params) : m_ring(ring), m_params(params) {
  const ShellGeometry& g = params.geometry;
  g.validate();
  if (ring.columns() != g.n_theta)
    throw std::invalid_argument("the ring has " + std::to_string(ring.columns()) + " columns, the shell " +
                                std::to_string(g.n_theta));
  if (!(params.alpha > 0.0) || !std::isfinite(params.alpha))
    throw std::invalid_argument("alpha must be finite and > 0");
  if (!(params.safety > 0.0 && params.safety <= 1.0)) throw std::invalid_argument("safety must be in (0, 1]");
  for (const HeatSource& s : params.sources)
    if (!(s.sigma > 0.0) || s.period == 0.0 || s.pulse_period == 0.0)
      throw std::invalid_argument("heat source: sigma must be > 0 and periods non-zero");

  // Forward Euler: stable while dt alpha (sum of the off-diagonal weights) <= 1, largest at r_1
  const double dr = g.dr(), dz = g.dz(), arc = g.radius(1) * g.dtheta();
  m_stable_dt = params.safety / (2.0 * params.alpha * (1.0 / (dr * dr) + 1.0 / (arc * arc) + 1.0 / (dz * dz)));

  m_column = g.n_r * g.n_z;
  const std::size_t n = static_cast<std::size_t>((ring.owned() + 2) * m_column);
  m_T.assign(n, params.initial_value);
  m_next.assign(n, params.initial_value);
  apply_walls(m_T);
  apply_walls(m_next);
  m_ring.exchange(m_T.data(), m_column);
}

void ShellSolver::apply_walls(std::vector<double>& field) const {
  const ShellGeometry& g = m_params.geometry;
  for (std::int64_t j = 0; j < m_ring.owned(); ++j) {
    for (std::int64_t i = 0; i < g.n_r; ++i) {
      field[index(i, j, 0)] = m_params.wall_value;
      field[index(i, j, g.n_z - 1)] = m_params.wall_value;
    }
    for (std::int64_t k = 0; k < g.n_z; ++k) {
      field[index(0, j, k)] = m_params.inner_value;
      field[index(g.n_r - 1, j, k)] = m_params.outer_value;
    }
  }
}

void ShellSolver::set_initial(const std::function<double(double, double, double)>& f) {
  const ShellGeometry& g = m_params.geometry;
  for (std::int64_t j = 0; j < m_ring.owned(); ++j)
    for (std::int64_t i = 0; i < g.n_r; ++i)
      for (std::int64_t k = 0; k < g.n_z; ++k)
        m_T[index(i, j, k)] = f(g.radius(i), g.theta(m_ring.offset() + j), g.z(k));
  apply_walls(m_T);
  m_ring.exchange(m_T.data(), m_column);
}

void ShellSolver::step(double dt) {
  if (!(dt > 0.0) || dt > m_stable_dt / m_params.safety)
    throw std::invalid_argument("time step " + std::to_string(dt) + " is outside (0, " +
                                std::to_string(m_stable_dt / m_params.safety) + "], the stability limit");
  const ShellGeometry& g = m_params.geometry;
  const double dr = g.dr(), dz = g.dz(), dtheta = g.dtheta(), alpha = m_params.alpha;
  const double cz = 1.0 / (dz * dz);
  const std::int64_t sj = m_column, si = g.n_z;
  // The sources at this step's time: centre, amplitude, 1 / (2 sigma^2)
  std::vector<std::array<double, 5>> sources;
  for (const HeatSource& src : m_params.sources) {
    const std::array<double, 3> centre = source_centre(src, m_time);
    sources.push_back(
        {centre[0], centre[1], centre[2], source_amplitude(src, m_time), 1.0 / (2.0 * src.sigma * src.sigma)});
  }

  // Diffusion and sources: every vertex off the walls from its six neighbours (the ghost
  // columns hold the neighbouring ranks' values)
  for (std::int64_t j = 0; j < m_ring.owned(); ++j) {
    const double theta = g.theta(m_ring.offset() + j);
    const double c = std::cos(theta), s = std::sin(theta);
    for (std::int64_t i = 1; i < g.n_r - 1; ++i) {
      const double r = g.radius(i);
      const double c_out = (r + 0.5 * dr) / (r * dr * dr), c_in = (r - 0.5 * dr) / (r * dr * dr);
      const double c_theta = 1.0 / (r * r * dtheta * dtheta);
      for (std::int64_t k = 1; k < g.n_z - 1; ++k) {
        const std::size_t v = index(i, j, k);
        const double T = m_T[v];
        const double lap = c_out * (m_T[v + si] - T) - c_in * (T - m_T[v - si]) +
                           c_theta * (m_T[v + sj] - 2.0 * T + m_T[v - sj]) + cz * (m_T[v + 1] - 2.0 * T + m_T[v - 1]);
        double q = 0.0;
        for (const std::array<double, 5>& src : sources) {
          const double dx = r * c - src[0], dy = r * s - src[1], dzz = g.z(k) - src[2];
          q += src[3] * std::exp(-(dx * dx + dy * dy + dzz * dzz) * src[4]);
        }
        m_next[v] = T + dt * (alpha * lap + q);
      }
    }
  }
  apply_walls(m_next);
  std::swap(m_T, m_next);
  m_time += dt;
  m_ring.exchange(m_T.data(), m_column);
}

std::pair<double, double> ShellSolver::local_range() const {
  double lo = m_T[index(0, 0, 0)], hi = lo;
  for (std::int64_t j = 0; j < m_ring.owned(); ++j)
    for (std::int64_t i = 0; i < m_params.geometry.n_r; ++i)
      for (std::int64_t k = 0; k < m_params.geometry.n_z; ++k) {
        lo = std::min(lo, m_T[index(i, j, k)]);
        hi = std::max(hi, m_T[index(i, j, k)]);
      }
  return {lo, hi};
}

}  // namespace heat
