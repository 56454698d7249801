// Test helper: small file systems a fault test can break on purpose: a tmpfs of a given size (to fill it) and
// a bind mount that can be switched read-only and back. Mounts are made in a private mount namespace of the
// calling thread when one can be had (so they vanish with the test process, whatever happens) and are
// unmounted when the object goes out of scope. Needs root (CAP_SYS_ADMIN); `unavailable` says why not.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace ogf::testing {

class ScratchMount {
 public:
  // A tmpfs of `size` ("256k", "16m") at `target` (created).
  static ScratchMount tmpfs(const std::filesystem::path& target, const std::string& size);
  // `source` bind-mounted at `target` (created).
  static ScratchMount bind(const std::filesystem::path& source, const std::filesystem::path& target);
  ~ScratchMount();
  ScratchMount(ScratchMount&& o) noexcept;
  ScratchMount& operator=(ScratchMount&&) = delete;
  ScratchMount(const ScratchMount&) = delete;
  ScratchMount& operator=(const ScratchMount&) = delete;

  // Why the mount could not be made (nullopt when it is in place).
  const std::optional<std::string>& unavailable() const { return unavailable_; }
  // Remounts read-only or read-write; the error when that failed.
  std::optional<std::string> setReadOnly(bool read_only);
  const std::filesystem::path& target() const { return target_; }

 private:
  ScratchMount() = default;
  std::filesystem::path target_;
  std::string data_;  // tmpfs options, kept for remounts
  bool bind_ = false;
  bool mounted_ = false;
  std::optional<std::string> unavailable_;
};

// Writes zeros into `path` until the file system is full; the bytes written.
std::uintmax_t fillFileSystem(const std::filesystem::path& path);

}  // namespace ogf::testing
