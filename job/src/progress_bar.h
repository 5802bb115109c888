#pragma once
// A one-line progress bar on stderr, redrawn in place.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace tessera::job {

class ProgressBar {
 public:
  /// A disabled bar draws nothing; `total` is the number of tiles.
  ProgressBar(std::string label, int total, bool enabled);
  /// Ends a line left open (a render that threw), so that an error message starts a line.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Tiles finished so far (core passes a running count). Thread-safe; redraws at most
  /// ten times a second; never blocks a worker (skips the redraw if another is drawing).
  void update(int done);
  /// Draws the full bar and ends the line.
  void finish();

 private:
  void draw(int done, bool force);
  std::string m_label;
  int m_total;
  bool m_enabled;
  std::atomic<int> m_done{0};
  std::mutex m_mutex;
  std::chrono::steady_clock::time_point m_start, m_last_draw;
  bool m_finished = false;
  bool m_drawn = false;
};

}  // namespace tessera::job
