#include "ogf/persistence/directory_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace ogf::persistence {
namespace {

constexpr const char* kLockFile = "lock";

std::string errnoText(int e) { return std::strerror(e); }

}  // namespace

LockOutcome DirectoryLock::acquire(const std::filesystem::path& dir) {
  LockOutcome out;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    out.message = dir.string() + ": cannot create the state directory: " + ec.message();
    return out;
  }
  const auto path = dir / kLockFile;
  bool writable = true;
  int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int e = errno;
    writable = false;
    fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      out.message = path.string() + ": cannot create the lock file: " + errnoText(e);
      return out;
    }
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    ::close(fd);
    if (e == EWOULDBLOCK) {
      const auto holder = holderOf(dir);
      out.in_use = true;
      out.message = dir.string() + " is in use by " +
                    (holder ? "process " + std::to_string(*holder) : std::string("another process")) +
                    " (it holds " + path.string() + "); a state directory has one mapper";
    } else {
      out.message = path.string() + ": cannot lock: " + errnoText(e);
    }
    return out;
  }
  // The holder's pid, for whoever is refused (best effort: a full disk keeps the lock without it).
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (writable && ::ftruncate(fd, 0) == 0) {
    [[maybe_unused]] const auto n = ::pwrite(fd, pid.data(), pid.size(), 0);
  }
  out.lock = DirectoryLock(fd, path);
  return out;
}

std::optional<pid_t> DirectoryLock::holderOf(const std::filesystem::path& dir) {
  std::ifstream in(dir / kLockFile);
  long pid = 0;
  if (!(in >> pid) || pid <= 0) return std::nullopt;
  return static_cast<pid_t>(pid);
}

DirectoryLock::DirectoryLock(DirectoryLock&& other) noexcept : fd_(other.fd_), path_(std::move(other.path_)) {
  other.fd_ = -1;
}

DirectoryLock& DirectoryLock::operator=(DirectoryLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    other.fd_ = -1;
  }
  return *this;
}

// Closing the descriptor releases the lock. The file stays: removing it would let a process that opened
// it just before lock a file no longer in the directory while a third locks a new one.
DirectoryLock::~DirectoryLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace ogf::persistence
