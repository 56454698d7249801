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

// Writes `bytes` to `path` through a temporary file beside it (`path` + ".tmp-" + the process id, so two
// processes writing one path never share it), fsync'd, renamed over `path`, then the directory fsync'd.
// Errors name the file (and the temporary one) and, for a write, the offset it stopped at; the temporary
// file is removed. An error from the directory's fsync comes after the rename: `path` then holds the new
// bytes, not yet durably.
inline Status writeFileAtomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  // Of the errno's kind: a full disk or quota is a resource error, the rest I/O.
  const auto fail = [&](const std::string& what, bool removeTmp) {
    const int e = errno;
    if (removeTmp) ::unlink(tmp.c_str());
    return Error::system(path.string() + ": " + what, e);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return fail("cannot create " + tmp.string(), false);
  if (const std::size_t done = writeAll(fd, bytes); done != bytes.size()) {
    auto err = fail("write failed at offset " + std::to_string(done), true);
    ::close(fd);
    return err;
  }
  if (::fsync(fd) != 0) {
    auto err = fail("fsync failed", true);
    ::close(fd);
    return err;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    return fail("rename from " + tmp.string() + " failed", true);
  }
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return Error::system(dir.string() + ": cannot open the directory to sync it", errno);
  const int rc = ::fsync(dfd);
  const int why = errno;
  ::close(dfd);
  if (rc != 0) return Error::system(dir.string() + ": fsync of the directory failed", why);
  return okStatus();
}

}  // namespace ogf
