// One owner per state directory: an exclusive flock(2) on <dir>/lock, held for the owner's whole life and
// released by the kernel when the process ends however it ends (kill -9 included), so a restart always
// gets it back. The file holds the owner's pid, so whoever is refused can name the holder.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>


namespace ogf::persistence {

class DirectoryLock;

// What acquiring gave: the lock; or in_use with the holder named in `message`; or neither when the
// directory cannot hold a lock file (not creatable, read-only without one, no space): nobody can write
// there then either, and `message` says why.
struct LockOutcome;

class DirectoryLock {
 public:
  // Creates `dir` when missing and takes its lock (a read-only directory's existing lock file is locked
  // too, so a second reader is refused all the same).
  static LockOutcome acquire(const std::filesystem::path& dir);

  DirectoryLock(DirectoryLock&& other) noexcept;
  DirectoryLock& operator=(DirectoryLock&& other) noexcept;
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  ~DirectoryLock();

  const std::filesystem::path& path() const { return path_; }

  // The pid written in a lock file (the holder's, while held), or nullopt when there is none.
  static std::optional<pid_t> holderOf(const std::filesystem::path& dir);

 private:
  DirectoryLock(int fd, std::filesystem::path path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::filesystem::path path_;
};

struct LockOutcome {
  std::optional<DirectoryLock> lock;
  bool in_use = false;
  std::string message;
};

}  // namespace ogf::persistence
