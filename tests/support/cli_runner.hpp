#pragma once
// Runs the `sinew` binary as a user would, for the CLI tests; and a temporary folder.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace sinew::test {

struct CliResult {
  int code = -1;
  std::string output;  // stdout and stderr
};

// `env_prefix` goes before the binary, e.g. "PATH=/x" (the shell sets it for sinew only).
inline CliResult run_sinew(const std::string& args, const std::string& env_prefix = "") {
  const std::string command = env_prefix + " " + std::string(SINEW_BINARY) + " " + args + " 2>&1";
  CliResult r;
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe);
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A fresh folder under the system temp dir, removed with the object.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("sinew_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string write(const std::string& file, const std::string& text) const {
    std::ofstream(path / file) << text;
    return (path / file).string();
  }
  std::string operator/(const std::string& file) const { return (path / file).string(); }
};

}  // namespace sinew::test
