// Reading a whole file into memory, telling a file that cannot be read (an I/O or resource error: the
// system's reason) from one that reads but holds the wrong bytes (for the caller's decoder to find).
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <filesystem>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf {

// Every byte of the file at `path`, or an Error of kind io or resource (Error::system) naming the file when
// it cannot be opened or read to its end: a directory, a file the process may not read, a failing disk.
inline Result<std::vector<std::byte>> readWholeFile(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    return Error::system(path.string() + ": cannot open", e);
  }
  struct stat st {};
  const bool sized = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  // One read past the size the file had, to see its end (or that it grew).
  std::vector<std::byte> bytes(sized ? static_cast<std::size_t>(st.st_size) + 1 : std::size_t{1} << 16);
  std::size_t done = 0;
  for (;;) {
    if (done == bytes.size()) bytes.resize(2 * bytes.size());
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int e = errno;
      ::close(fd);
      return Error::system(path.string() + ": cannot read", e);
    }
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

}  // namespace ogf
