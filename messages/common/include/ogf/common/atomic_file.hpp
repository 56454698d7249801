// Writing a file so a crash leaves either the old file or the new one, never a mix: write a temporary file
// beside it, fsync it, rename it over the target, fsync the directory (the rename is durable only then).
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf {

// Writes all of `bytes` to `fd`, continuing short writes and retrying interrupted ones. Returns how many
// bytes were written: fewer than bytes.size() when a write failed, with errno saying why.
inline std::size_t writeAll(int fd, std::span<const std::byte> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  return done;
}

// Makes a rename or creation of `path` durable: fsync of the directory holding it (best effort).
inline void syncParentDirectory(const std::filesystem::path& path) {
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

inline Status writeFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  // Of the errno's kind: a full disk or quota is a resource error, the rest I/O.
  const auto fail = [&](const std::string& what) {
    const int e = errno;
    return Error::system(path.string() + ": " + what, e);
  };
  const std::filesystem::path tmp = path.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return fail("cannot create " + tmp.string());
  if (writeAll(fd, bytes) != bytes.size()) {
    auto err = fail("write failed");
    ::close(fd);
    ::unlink(tmp.c_str());
    return err;
  }
  if (::fsync(fd) != 0) {
    auto err = fail("fsync failed");
    ::close(fd);
    ::unlink(tmp.c_str());
    return err;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    auto err = fail("rename failed");
    ::unlink(tmp.c_str());
    return err;
  }
  syncParentDirectory(path);
  return okStatus();
}

}  // namespace ogf
