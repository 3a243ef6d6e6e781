// Atomic file writes: temporary sibling + rename(2). See atomic_file.h.
#include "atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "qualmesh/error.h"

namespace qualmesh::io {

namespace {
std::string temporary_name(const std::string& path) {
  // Unique per process and call; no randomness leaks into the output itself.
  static std::mt19937_64 generator{std::random_device{}()};
  static const char* digits = "0123456789abcdefghijklmnopqrstuvwxyz";
  std::string name = path + ".tmp-";
  for (int i = 0; i < 8; ++i) name += digits[generator() % 36];
  return name;
}
}  // namespace

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.has_parent_path() && !fs::is_directory(target.parent_path())) {
    throw InputError(ErrorCode::Io, "folder '" + target.parent_path().string() + "' does not exist", path);
  }
  const std::string temp = temporary_name(path);
  try {
    {
      std::ofstream out(temp, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw InputError(ErrorCode::Io, std::string("cannot create file: ") + std::strerror(errno), path);
      }
      fill(out);
      out.flush();
      if (!out) throw InputError(ErrorCode::Io, "write failed (disk full?)", path);
    }
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw InputError(ErrorCode::Io, "cannot rename temporary file into place: " + ec.message(), path);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw;
  }
}

}  // namespace qualmesh::io
