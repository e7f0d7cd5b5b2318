#pragma once
// Progress report for long loops. On a terminal: one bar redrawn in place (at most ~10 times
// a second) with an ETA. Otherwise (logs, pipes): a plain line every 10%. Silent if total == 0.
#include <chrono>
#include <cstdio>
#include <string>

namespace sinew {

class Progress {
 public:
  Progress(std::string label, int total, std::FILE* out = stderr);
  ~Progress();  // finishes, so that an exception does not leave the bar's line open
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(int done);
  void finish();  // final state and newline; later calls do nothing

 private:
  using Clock = std::chrono::steady_clock;
  void draw_bar();

  std::string m_label;
  int m_total;
  std::FILE* m_out;
  bool m_tty = false;
  bool m_finished = false;
  int m_done = 0;
  int m_printed_decile = 0;   // plain mode: last 10% step printed (0% is not)
  int m_printed_done = -1;
  int m_line_length = 0;      // bar mode: to blank out leftovers of a longer previous line
  Clock::time_point m_start = Clock::now();
  Clock::time_point m_last_draw{};
  bool m_drawn = false;
};

}  // namespace sinew
