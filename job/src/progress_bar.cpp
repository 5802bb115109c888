#include "progress_bar.h"

#include <algorithm>
#include <cstdio>

namespace tessera::job {

ProgressBar::ProgressBar(std::string label, int total, bool enabled)
    : m_label(std::move(label)),
      m_total(std::max(total, 1)),
      m_enabled(enabled),
      m_start(std::chrono::steady_clock::now()),
      m_last_draw(m_start - std::chrono::seconds(1)) {}

ProgressBar::~ProgressBar() {
  if (m_drawn && !m_finished) std::fputc('\n', stderr);
}

void ProgressBar::update(int done) {
  if (!m_enabled) return;
  // Keep the largest count seen: calls may arrive out of order from different workers
  int prev = m_done.load();
  while (done > prev && !m_done.compare_exchange_weak(prev, done)) {
  }
  std::unique_lock lock(m_mutex, std::try_to_lock);
  if (!lock.owns_lock()) return;
  draw(m_done.load(), false);
}

void ProgressBar::finish() {
  if (!m_enabled) return;
  std::lock_guard lock(m_mutex);
  if (m_finished) return;
  draw(m_total, true);
  std::fputc('\n', stderr);
  std::fflush(stderr);
  m_finished = true;
}

void ProgressBar::draw(int done, bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - m_last_draw < std::chrono::milliseconds(100)) return;
  m_last_draw = now;
  m_drawn = true;
  constexpr int kWidth = 30;
  const double frac = std::clamp(double(done) / m_total, 0.0, 1.0);
  const int filled = static_cast<int>(frac * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '=' : (i == filled ? '>' : ' ');
  bar[kWidth] = '\0';
  const double secs = std::chrono::duration<double>(now - m_start).count();
  std::fprintf(stderr, "\r%s [%s] %3d%% %d/%d tiles %.1fs", m_label.c_str(), bar, static_cast<int>(frac * 100.0),
               std::min(done, m_total), m_total, secs);
  std::fflush(stderr);
}

}  // namespace tessera::job
