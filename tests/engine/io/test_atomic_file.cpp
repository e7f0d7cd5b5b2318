#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/io/atomic_file.hpp"

namespace fs = std::filesystem;

namespace {

// A fresh folder per test case: ctest runs cases of one binary in parallel.
fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sinew_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int count_entries(const fs::path& d) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(d)) n += e.exists();
  return n;
}

}  // namespace

TEST_CASE("io: write_file_atomically leaves nothing when the writer throws") {
  const fs::path d = fresh_dir("atomic_throw");
  const std::string path = (d / "out.txt").string();
  try {
    sinew::write_file_atomically(path, [](std::ostream& out) {
      out << std::string(100000, 'x');  // big enough to have reached the disk
      out.flush();
      throw std::logic_error("boom");
    });
    FAIL("expected an exception");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find(path) != std::string::npos);
    CHECK(std::string(e.what()).find("boom") != std::string::npos);
  }
  CHECK(!fs::exists(path));
  CHECK(count_entries(d) == 0);  // no temp file either
  fs::remove_all(d);
}

TEST_CASE("io: write_file_atomically keeps the old file when a write fails") {
  const fs::path d = fresh_dir("atomic_keep");
  const std::string path = (d / "out.txt").string();
  sinew::write_file_atomically(path, [](std::ostream& out) { out << "old\n"; });
  CHECK_THROWS_AS(sinew::write_file_atomically(path,
                                               [](std::ostream& out) {
                                                 out << "partial";
                                                 out.setstate(std::ios::badbit);  // a failing disk
                                               }),
                  std::runtime_error);
  CHECK(slurp(path) == "old\n");
  CHECK(count_entries(d) == 1);
  fs::remove_all(d);
}

TEST_CASE("io: write_file_atomically replaces an existing file") {
  const fs::path d = fresh_dir("atomic_replace");
  const std::string path = (d / "out.txt").string();
  {
    std::ofstream(path) << "a much longer old content that must not survive\n";
  }
  sinew::write_file_atomically(path, [](std::ostream& out) { out << "new\n" << 0.5 << '\n'; });
  CHECK(slurp(path) == "new\n0.5\n");
  CHECK(count_entries(d) == 1);
  fs::remove_all(d);
}

TEST_CASE("io: write_file_atomically into a missing folder throws naming the path") {
  const fs::path d = fresh_dir("atomic_missing");
  const std::string path = (d / "no_such_dir" / "out.txt").string();
  CHECK_THROWS_WITH_AS(sinew::write_file_atomically(path, [](std::ostream& out) { out << "x"; }),
                       doctest::Contains(path.c_str()), std::runtime_error);
  CHECK(count_entries(d) == 0);
  fs::remove_all(d);
}

TEST_CASE("io: ensure_directory creates parents and rejects files") {
  const fs::path d = fresh_dir("ensure_dir");
  const fs::path nested = d / "a" / "b" / "c";
  sinew::ensure_directory(nested.string());
  CHECK(fs::is_directory(nested));
  sinew::ensure_directory(nested.string());  // existing folder is fine
  const fs::path file = d / "file";
  std::ofstream(file) << "x";
  CHECK_THROWS_WITH_AS(sinew::ensure_directory(file.string()), doctest::Contains(file.string().c_str()),
                       std::runtime_error);
  CHECK_THROWS_AS(sinew::ensure_directory((file / "sub").string()), std::runtime_error);
  fs::remove_all(d);
}
