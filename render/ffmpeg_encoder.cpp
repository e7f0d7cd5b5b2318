#include "render/ffmpeg_encoder.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "render/render_error.hpp"

extern char** environ;

namespace sinew {
namespace fs = std::filesystem;
namespace {

// Writes everything, returning false on EPIPE (reader gone) instead of dying of SIGPIPE:
// SIGPIPE is blocked for this thread during the write and a pending one is consumed.
bool write_all(int fd, const uint8_t* data, size_t size) {
  sigset_t pipe_set, old_set;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old_set);
  bool ok = true;
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = false;
      break;
    }
    data += n, size -= size_t(n);
  }
  if (!ok && errno == EPIPE) {
    const timespec zero{0, 0};
    sigtimedwait(&pipe_set, nullptr, &zero);
  }
  pthread_sigmask(SIG_SETMASK, &old_set, nullptr);
  return ok;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

std::string find_in_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate.string();
  }
  return "";
}

std::string require_ffmpeg() {
  const std::string ffmpeg = find_in_path("ffmpeg");
  if (ffmpeg.empty())
    throw RenderError("recording a video needs the ffmpeg program, which is not in PATH (" +
                      std::string(std::getenv("PATH") ? std::getenv("PATH") : "") +
                      "); install it (Debian: apt-get install ffmpeg)");
  return ffmpeg;
}

FfmpegEncoder::FfmpegEncoder(const VideoFormat& format, const std::string& ffmpeg, const std::string& output)
    : m_format(format), m_output(output) {
  if (format.width < 2 || format.height < 2 || format.width % 2 || format.height % 2)
    throw RenderError("video size " + std::to_string(format.width) + "x" + std::to_string(format.height) +
                      " must be even in both directions (H.264 yuv420p)");
  const fs::path out(output);
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw RenderError("cannot record '" + output + "': folder '" + dir.string() + "' does not exist");
  m_temp = (dir / ("." + out.filename().string() + ".partial-" + std::to_string(getpid()))).string();
  m_log = m_temp + ".log";

  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) throw RenderError(std::string("pipe() failed: ") + std::strerror(errno));
  const std::string size = std::to_string(format.width) + "x" + std::to_string(format.height);
  // The muxer is named because the temporary file's name does not end in .mp4.
  std::vector<std::string> args = {ffmpeg, "-hide_banner", "-loglevel", "error", "-nostdin",
                                   "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", size, "-r", number(format.fps),
                                   "-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-f", "mp4", "-y", m_temp};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[0], 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, m_log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  const int err = posix_spawn(&m_pid, ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[0]);
  if (err != 0) {
    ::close(pipe_fds[1]);
    m_pid = -1;
    throw RenderError("cannot start '" + ffmpeg + "': " + std::strerror(err));
  }
  m_stdin = pipe_fds[1];
}

FfmpegEncoder::~FfmpegEncoder() {
  if (m_pid > 0) stop(true);
  std::error_code ignored;
  fs::remove(m_temp, ignored);
  fs::remove(m_log, ignored);
}

void FfmpegEncoder::stop(bool kill_first) {
  if (m_stdin >= 0) ::close(m_stdin), m_stdin = -1;
  if (m_pid <= 0) return;
  if (kill_first) ::kill(m_pid, SIGKILL);
  while (waitpid(m_pid, &m_status, 0) < 0 && errno == EINTR) {
  }
  m_pid = -1;
}

std::string FfmpegEncoder::log_tail() const {
  std::ifstream in(m_log);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() > 2000) text = "..." + text.substr(text.size() - 2000);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text.empty() ? "(ffmpeg printed nothing)" : text;
}

void FfmpegEncoder::write_frame(const uint8_t* rgb) {
  if (m_stdin < 0) throw RenderError("video '" + m_output + "': frame written after the end");
  if (!write_all(m_stdin, rgb, size_t(3) * m_format.width * m_format.height)) {
    const int error = errno;
    stop(false);
    throw RenderError("ffmpeg stopped reading frames for '" + m_output + "' (" + std::strerror(error) + "):\n" +
                      log_tail());
  }
}

void FfmpegEncoder::finish() {
  stop(false);
  if (!WIFEXITED(m_status) || WEXITSTATUS(m_status) != 0) {
    const std::string how = WIFEXITED(m_status) ? "exit code " + std::to_string(WEXITSTATUS(m_status))
                                                 : "signal " + std::to_string(WTERMSIG(m_status));
    throw RenderError("ffmpeg failed to write '" + m_output + "' (" + how + "):\n" + log_tail());
  }
  std::error_code ec;
  fs::remove(m_log, ec);
  fs::rename(m_temp, m_output, ec);
  if (ec) throw RenderError("cannot move the video into place as '" + m_output + "': " + ec.message());
}

}  // namespace sinew
