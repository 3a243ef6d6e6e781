// Reading an input file whole, safely: see file_read.h. Opened with O_NONBLOCK so that opening a FIFO does not wait
// for a writer; fstat on the open descriptor then decides (no race between the check and the read).
#include "file_read.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"

namespace qualmesh::io_detail {

namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory, not a file";
  if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(mode)) return "is a character device (such as /dev/zero), not a regular file";
  if (S_ISBLK(mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

std::string link_note(const std::string& path) {
  struct stat ls;
  if (lstat(path.c_str(), &ls) != 0 || !S_ISLNK(ls.st_mode)) return "";
  char target[4096];
  const ssize_t n = readlink(path.c_str(), target, sizeof target - 1);
  if (n <= 0) return " (a symbolic link)";
  return " (a symbolic link to " + std::string(target, std::size_t(n)) + ")";
}

struct Descriptor {
  int fd;
  explicit Descriptor(int f) : fd(f) {}
  Descriptor(Descriptor&& other) noexcept : fd(other.fd) { other.fd = -1; }
  Descriptor(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd >= 0) close(fd);
  }
};

// Opens `path` without blocking and refuses what is not a regular file; the descriptor and its size.
Descriptor open_regular(const std::string& path, off_t& size) {
  Descriptor file{open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) throw InputError(ErrorCode::Io, std::string("cannot open file: ") + std::strerror(errno), path);
  struct stat st;
  if (fstat(file.fd, &st) != 0) throw InputError(ErrorCode::Io, std::string("cannot stat file: ") + std::strerror(errno), path);
  if (!S_ISREG(st.st_mode)) throw InputError(ErrorCode::Io, kind_of(st.st_mode) + link_note(path), path);
  size = st.st_size;
  return file;
}

}  // namespace

void require_regular_file(const std::string& path) {
  off_t size = 0;
  (void)open_regular(path, size);
}

std::string as_text(std::string bytes) {
  if (bytes.size() >= 3 && bytes.compare(0, 3, "\xEF\xBB\xBF") == 0) bytes.erase(0, 3);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (bytes[i] == '\r' && (i + 1 == bytes.size() || bytes[i + 1] != '\n')) bytes[i] = '\n';
  }
  return bytes;
}

std::string read_regular_file(const std::string& path) {
  off_t size = 0;
  Descriptor file = open_regular(path, size);
  std::string data(static_cast<std::size_t>(size), '\0');
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = read(file.fd, &data[done], data.size() - done);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n < 0) throw InputError(ErrorCode::Io, std::string("read failed: ") + std::strerror(errno), path);
    if (n == 0) break;  // shrank while being read
    done += std::size_t(n);
  }
  data.resize(done);
  return data;
}

}  // namespace qualmesh::io_detail

namespace qualmesh {
void require_regular_input_file(const std::string& path) { io_detail::require_regular_file(path); }
}  // namespace qualmesh
