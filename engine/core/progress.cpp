#include "engine/core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <utility>

namespace sinew {

namespace {

std::string format_eta(double seconds) {
  char buf[32];
  if (seconds < 60) std::snprintf(buf, sizeof buf, "%.1f s", seconds);
  else if (seconds < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(seconds) / 3600, int(seconds) / 60 % 60);
  return buf;
}

}  // namespace

Progress::Progress(std::string label, int total, std::FILE* out)
    : m_label(std::move(label)), m_total(std::max(total, 0)), m_out(out) {
  if (m_out) m_tty = ::isatty(::fileno(m_out)) == 1;
}

Progress::~Progress() { finish(); }

void Progress::update(int done) {
  if (m_total == 0 || !m_out || m_finished) return;
  m_done = std::clamp(done, 0, m_total);
  if (m_tty) {
    const Clock::time_point now = Clock::now();
    if (m_drawn && now - m_last_draw < std::chrono::milliseconds(100)) return;
    m_last_draw = now;
    draw_bar();
    return;
  }
  const int decile = int(10LL * m_done / m_total);
  if (decile <= m_printed_decile) return;
  m_printed_decile = decile;
  m_printed_done = m_done;
  std::fprintf(m_out, "%s: %d/%d (%d%%)\n", m_label.c_str(), m_done, m_total, int(100LL * m_done / m_total));
  std::fflush(m_out);
}

void Progress::finish() {
  if (m_finished) return;
  m_finished = true;
  if (m_total == 0 || !m_out) return;
  if (m_tty) {
    draw_bar();
    std::fputc('\n', m_out);
  } else if (m_printed_done != m_done) {
    std::fprintf(m_out, "%s: %d/%d (%d%%)\n", m_label.c_str(), m_done, m_total, int(100LL * m_done / m_total));
  }
  std::fflush(m_out);
}

void Progress::draw_bar() {
  constexpr int kWidth = 20;
  const int filled = int(1LL * kWidth * m_done / m_total);
  std::string bar(filled, '#');
  bar.append(kWidth - filled, '.');
  std::string eta = "--";
  const double elapsed = std::chrono::duration<double>(Clock::now() - m_start).count();
  if (m_done > 0) eta = format_eta(elapsed * (m_total - m_done) / m_done);
  char line[512];
  int n = std::snprintf(line, sizeof line, "%s [%s] %d/%d  %3d%%  ETA %s", m_label.c_str(), bar.c_str(), m_done,
                        m_total, int(100LL * m_done / m_total), eta.c_str());
  n = std::clamp(n, 0, int(sizeof line) - 1);
  std::fprintf(m_out, "\r%s%*s", line, std::max(m_line_length - n, 0), "");
  m_line_length = n;
  m_drawn = true;
  std::fflush(m_out);
}

}  // namespace sinew
