#include "heat_solver.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace heat {

HeatSolver::HeatSolver(const CartDecomposition& decomp, const HeatParams& params)
    : m_decomp(decomp), m_params(params), m_halo(decomp) {
  const Index3& g = decomp.global_dims();
  for (int a = 0; a < 3; ++a) {
    if (g[a] < 3)
      throw std::invalid_argument("grid axis " + std::to_string(a) + " has " + std::to_string(g[a]) +
                                  " vertices; at least 3 are needed (two walls and an interior)");
    m_h[a] = 1.0 / static_cast<double>(g[a] - 1);
    m_dims[a] = decomp.owned()[a] + 2;
  }
  if (!(params.alpha > 0.0) || !std::isfinite(params.alpha))
    throw std::invalid_argument("alpha must be finite and > 0");
  if (!(params.safety > 0.0 && params.safety <= 1.0)) throw std::invalid_argument("safety must be in (0, 1]");
  for (const HeatSource& s : params.sources)
    if (!(s.sigma > 0.0) || s.period == 0.0 || s.pulse_period == 0.0)
      throw std::invalid_argument("heat source: sigma must be > 0 and periods non-zero");

  // Forward Euler with the 7-point Laplacian is stable for dt * alpha * sum(4 / h^2) <= 2.
  const double inv_h2 = 1.0 / (m_h[0] * m_h[0]) + 1.0 / (m_h[1] * m_h[1]) + 1.0 / (m_h[2] * m_h[2]);
  m_stable_dt = params.safety / (2.0 * params.alpha * inv_h2);

  const std::size_t n = static_cast<std::size_t>(m_dims[0] * m_dims[1] * m_dims[2]);
  m_T.assign(n, params.initial_value);
  m_next.assign(n, params.initial_value);
  apply_walls(m_T);
  apply_walls(m_next);
  m_halo.exchange(m_T.data());
}

void HeatSolver::apply_walls(std::vector<double>& field) const {
  const Index3& g = m_decomp.global_dims();
  const Index3& off = m_decomp.offset();
  const Index3& n = m_decomp.owned();
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const std::int64_t gi = off[0] + i, gj = off[1] + j, gk = off[2] + k;
        if (gi == 0 || gj == 0 || gk == 0 || gi == g[0] - 1 || gj == g[1] - 1 || gk == g[2] - 1)
          field[index(i, j, k)] = m_params.boundary_value;
      }
}

void HeatSolver::set_initial(const std::function<double(double, double, double)>& f) {
  const Index3& off = m_decomp.offset();
  const Index3& n = m_decomp.owned();
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i)
        m_T[index(i, j, k)] = f(static_cast<double>(off[0] + i) * m_h[0], static_cast<double>(off[1] + j) * m_h[1],
                                static_cast<double>(off[2] + k) * m_h[2]);
  apply_walls(m_T);
  m_halo.exchange(m_T.data());
}

void HeatSolver::step(double dt) {
  if (!(dt > 0.0) || dt > m_stable_dt / m_params.safety)
    throw std::invalid_argument("time step " + std::to_string(dt) + " is outside (0, " +
                                std::to_string(m_stable_dt / m_params.safety) + "], the stability limit");
  const Index3& g = m_decomp.global_dims();
  const Index3& off = m_decomp.offset();
  const Index3& n = m_decomp.owned();
  const double cx = m_params.alpha / (m_h[0] * m_h[0]);
  const double cy = m_params.alpha / (m_h[1] * m_h[1]);
  const double cz = m_params.alpha / (m_h[2] * m_h[2]);
  const std::int64_t sy = m_dims[0], sz = m_dims[0] * m_dims[1];

  // Diffusion: interior vertices from their six neighbours (ghosts hold the neighbours' values)
  for (std::int64_t k = 0; k < n[2]; ++k) {
    const std::int64_t gk = off[2] + k;
    for (std::int64_t j = 0; j < n[1]; ++j) {
      const std::int64_t gj = off[1] + j;
      const bool wall_row = gk == 0 || gk == g[2] - 1 || gj == 0 || gj == g[1] - 1;
      const std::size_t row = index(0, j, k);
      for (std::int64_t i = 0; i < n[0]; ++i) {
        const std::int64_t gi = off[0] + i;
        const std::size_t c = row + static_cast<std::size_t>(i);
        if (wall_row || gi == 0 || gi == g[0] - 1) {
          m_next[c] = m_params.boundary_value;
          continue;
        }
        const double T = m_T[c];
        const double lap = cx * (m_T[c - 1] - 2.0 * T + m_T[c + 1]) + cy * (m_T[c - sy] - 2.0 * T + m_T[c + sy]) +
                           cz * (m_T[c - sz] - 2.0 * T + m_T[c + sz]);
        m_next[c] = T + dt * lap;
      }
    }
  }
  add_sources(dt);
  m_T.swap(m_next);
  m_time += dt;
  ++m_steps;
  m_halo.exchange(m_T.data());
}

void HeatSolver::add_sources(double dt) {
  // Each source heats the interior vertices within 6 sigma of its centre at the step's start
  // time (forward Euler); beyond, exp(-18) of its peak is dropped.
  const Index3& g = m_decomp.global_dims();
  const Index3& off = m_decomp.offset();
  const Index3& n = m_decomp.owned();
  for (const HeatSource& s : m_params.sources) {
    const std::array<double, 3> c = source_centre(s, m_time);
    const double amp = dt * source_amplitude(s, m_time);
    const double reach = 6.0 * s.sigma, inv_2s2 = 1.0 / (2.0 * s.sigma * s.sigma);
    std::int64_t lo[3], hi[3];  // owned local index range within reach, walls excluded
    for (int a = 0; a < 3; ++a) {
      const std::int64_t glo = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((c[a] - reach) / m_h[a])));
      const std::int64_t ghi =
          std::min<std::int64_t>(g[a] - 2, static_cast<std::int64_t>(std::floor((c[a] + reach) / m_h[a])));
      lo[a] = std::max<std::int64_t>(glo - off[a], 0);
      hi[a] = std::min<std::int64_t>(ghi - off[a], n[a] - 1);
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
          const double dx = static_cast<double>(off[0] + i) * m_h[0] - c[0];
          const double dy = static_cast<double>(off[1] + j) * m_h[1] - c[1];
          const double dz = static_cast<double>(off[2] + k) * m_h[2] - c[2];
          m_next[index(i, j, k)] += amp * std::exp(-(dx * dx + dy * dy + dz * dz) * inv_2s2);
        }
  }
}

std::pair<double, double> HeatSolver::local_range() const {
  const Index3& n = m_decomp.owned();
  double lo = m_T[index(0, 0, 0)], hi = lo;
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) {
        lo = std::min(lo, m_T[index(i, j, k)]);
        hi = std::max(hi, m_T[index(i, j, k)]);
      }
  return {lo, hi};
}

}  // namespace heat
