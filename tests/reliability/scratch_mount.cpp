#include "scratch_mount.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace ogf::testing {
namespace {

std::string systemError(const std::string& what) { return what + ": " + std::strerror(errno); }

// Once per thread: a mount namespace of our own with private propagation, so nothing mounted here is seen
// by (or left behind in) the host's. Best effort: without it the mounts are still made and unmounted.
void enterPrivateMountNamespace() {
  thread_local bool done = false;
  if (done) return;
  done = true;
  if (::unshare(CLONE_NEWNS) == 0) ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr);
}

std::optional<std::string> prerequisites() {
  if (::geteuid() != 0) return std::string("not root: mounting a tmpfs or a bind mount needs CAP_SYS_ADMIN");
  return std::nullopt;
}

}  // namespace

ScratchMount ScratchMount::tmpfs(const std::filesystem::path& target, const std::string& size) {
  ScratchMount m;
  m.target_ = target;
  m.data_ = "size=" + size + ",mode=0755";
  if ((m.unavailable_ = prerequisites())) return m;
  enterPrivateMountNamespace();
  std::error_code ec;
  std::filesystem::create_directories(target, ec);
  if (::mount("ogf-test", target.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, m.data_.c_str()) != 0) {
    m.unavailable_ = systemError("mount -t tmpfs -o " + m.data_ + " " + target.string());
    return m;
  }
  m.mounted_ = true;
  return m;
}

ScratchMount ScratchMount::bind(const std::filesystem::path& source, const std::filesystem::path& target) {
  ScratchMount m;
  m.target_ = target;
  m.bind_ = true;
  if ((m.unavailable_ = prerequisites())) return m;
  enterPrivateMountNamespace();
  std::error_code ec;
  std::filesystem::create_directories(target, ec);
  if (::mount(source.c_str(), target.c_str(), nullptr, MS_BIND, nullptr) != 0) {
    m.unavailable_ = systemError("mount --bind " + source.string() + " " + target.string());
    return m;
  }
  m.mounted_ = true;
  return m;
}

ScratchMount::ScratchMount(ScratchMount&& o) noexcept
    : target_(std::move(o.target_)),
      data_(std::move(o.data_)),
      bind_(o.bind_),
      mounted_(o.mounted_),
      unavailable_(std::move(o.unavailable_)) {
  o.mounted_ = false;
}

ScratchMount::~ScratchMount() {
  if (mounted_) ::umount2(target_.c_str(), MNT_DETACH);
}

std::optional<std::string> ScratchMount::setReadOnly(bool read_only) {
  if (!mounted_) return std::string("not mounted");
  unsigned long flags = MS_REMOUNT | MS_NOSUID | MS_NODEV;
  if (bind_) flags = MS_REMOUNT | MS_BIND;
  if (read_only) flags |= MS_RDONLY;
  if (::mount(nullptr, target_.c_str(), nullptr, flags, bind_ ? nullptr : data_.c_str()) != 0)
    return systemError(std::string("mount -o remount,") + (read_only ? "ro " : "rw ") + target_.string());
  return std::nullopt;
}

std::uintmax_t fillFileSystem(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return 0;
  const std::vector<char> zeros(64 * 1024, 0);
  std::uintmax_t total = 0;
  for (std::size_t chunk = zeros.size(); chunk > 0;) {
    const ssize_t n = ::write(fd, zeros.data(), chunk);
    if (n > 0) {
      total += static_cast<std::uintmax_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      chunk /= 2;  // ENOSPC: fill the last pages with smaller writes
    }
  }
  ::fsync(fd);
  ::close(fd);
  return total;
}

}  // namespace ogf::testing
