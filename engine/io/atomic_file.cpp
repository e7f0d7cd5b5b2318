#include "engine/io/atomic_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <locale>
#include <stdexcept>
#include <system_error>

namespace sinew {

namespace fs = std::filesystem;

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  // Same folder as the target so that rename stays on one file system (atomic).
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::string error;
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      error = "cannot create temporary file '" + tmp + "'";
    } else {
      // Output files are read by other programs: numbers must not follow the user's locale.
      out.imbue(std::locale::classic());
      write(out);
      out.close();  // flushes; a full disk shows up here
      if (out.fail()) error = "stream error while writing";
    }
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown exception";
  }
  if (error.empty()) {
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) error = "rename failed: " + ec.message();
  }
  if (!error.empty()) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot write '" + path + "': " + error);
  }
}

void ensure_directory(const std::string& path) {
  if (path.empty()) return;  // the current folder
  std::error_code ec;
  fs::create_directories(path, ec);
  if (!ec && !fs::is_directory(path, ec) && !ec)
    throw std::runtime_error("cannot create directory '" + path + "': a file of that name exists");
  if (ec) throw std::runtime_error("cannot create directory '" + path + "': " + ec.message());
}

}  // namespace sinew
