#include "heat_solver.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace heat {

std::array<double, 3> checked_spacing(const CartDecomposition& decomp, const HeatParams& params) {
  const Index3& g = decomp.global_dims();
  std::array<double, 3> h{};
  for (int a = 0; a < 3; ++a) {
    if (g[a] < 3)
      throw std::invalid_argument("grid axis " + std::to_string(a) + " has " + std::to_string(g[a]) +
                                  " vertices; at least 3 are needed (two walls and an interior)");
    h[a] = 1.0 / static_cast<double>(g[a] - 1);
  }
  if (!(params.alpha > 0.0) || !std::isfinite(params.alpha))
    throw std::invalid_argument("alpha must be finite and > 0");
  if (!(params.safety > 0.0 && params.safety <= 1.0)) throw std::invalid_argument("safety must be in (0, 1]");
  for (const HeatSource& s : params.sources)
    if (!(s.sigma > 0.0) || s.period == 0.0 || s.pulse_period == 0.0)
      throw std::invalid_argument("heat source: sigma must be > 0 and periods non-zero");
  return h;
}

double stable_time_step(const std::array<double, 3>& h, const HeatParams& params) {
  // Forward Euler with the 7-point Laplacian is stable for dt * alpha * sum(4 / h^2) <= 2.
  const double inv_h2 = 1.0 / (h[0] * h[0]) + 1.0 / (h[1] * h[1]) + 1.0 / (h[2] * h[2]);
  return params.safety / (2.0 * params.alpha * inv_h2);
}

void check_time_step(double dt, double stable_dt, double safety) {
  if (!(dt > 0.0) || dt > stable_dt / safety)
    throw std::invalid_argument("time step " + std::to_string(dt) + " is outside (0, " +
                                std::to_string(stable_dt / safety) + "], the stability limit");
}

SourceStamp source_stamp(const HeatSource& s, double t, double dt, const CartDecomposition& decomp,
                         const std::array<double, 3>& h) {
  const Index3& g = decomp.global_dims();
  const Index3& off = decomp.offset();
  const Index3& n = decomp.owned();
  const std::array<double, 3> c = source_centre(s, t);
  SourceStamp st{};
  st.amp = dt * source_amplitude(s, t);
  st.inv_2s2 = 1.0 / (2.0 * s.sigma * s.sigma);
  const double reach = 6.0 * s.sigma;
  for (int a = 0; a < 3; ++a) {  // owned local index range within reach, walls excluded
    const std::int64_t glo = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((c[a] - reach) / h[a])));
    const std::int64_t ghi =
        std::min<std::int64_t>(g[a] - 2, static_cast<std::int64_t>(std::floor((c[a] + reach) / h[a])));
    st.centre[a] = c[a];
    st.lo[a] = std::max<std::int64_t>(glo - off[a], 0);
    st.hi[a] = std::min<std::int64_t>(ghi - off[a], n[a] - 1);
  }
  return st;
}

HeatSolver::HeatSolver(const CartDecomposition& decomp, const HeatParams& params)
    : m_decomp(decomp), m_params(params), m_halo(decomp) {
  m_h = checked_spacing(decomp, params);
  for (int a = 0; a < 3; ++a) m_dims[a] = decomp.owned()[a] + 2;
  m_stable_dt = stable_time_step(m_h, params);

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
  check_time_step(dt, m_stable_dt, m_params.safety);
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
  // Each source heats the interior vertices near its centre at the step's start time (forward
  // Euler), one source after the other
  const Index3& off = m_decomp.offset();
  for (const HeatSource& s : m_params.sources) {
    const SourceStamp st = source_stamp(s, m_time, dt, m_decomp, m_h);
    for (std::int64_t k = st.lo[2]; k <= st.hi[2]; ++k)
      for (std::int64_t j = st.lo[1]; j <= st.hi[1]; ++j)
        for (std::int64_t i = st.lo[0]; i <= st.hi[0]; ++i) {
          const double dx = static_cast<double>(off[0] + i) * m_h[0] - st.centre[0];
          const double dy = static_cast<double>(off[1] + j) * m_h[1] - st.centre[1];
          const double dz = static_cast<double>(off[2] + k) * m_h[2] - st.centre[2];
          m_next[index(i, j, k)] += st.amp * std::exp(-(dx * dx + dy * dy + dz * dz) * st.inv_2s2);
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

std::vector<double> HeatSolver::owned_values() const {
  const Index3& n = m_decomp.owned();
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  for (std::int64_t k = 0; k < n[2]; ++k)
    for (std::int64_t j = 0; j < n[1]; ++j)
      for (std::int64_t i = 0; i < n[0]; ++i) v.push_back(m_T[index(i, j, k)]);
  return v;
}

}  // namespace heat
