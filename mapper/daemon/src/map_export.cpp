// Map exports into the export directory: see map_export.hpp.
#include "ogf/mapper_daemon/map_export.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ogf::mapper_daemon {
namespace {

const char* const kFormats[] = {"ogfm", "ply", "pcd", "csv", "bt"};

std::string errnoText() { return std::strerror(errno); }

std::string procPath(int fd) { return "/proc/self/fd/" + std::to_string(fd); }

}  // namespace

bool knownExportFormat(const std::string& format) {
  for (const char* f : kFormats) {
    if (format == f) return true;
  }
  return false;
}

Status checkExportName(const std::string& name, const std::string& format) {
  if (!knownExportFormat(format)) return Error{"format '" + format + "': ogfm, ply, pcd, csv or bt"};
  if (name.empty() || name.size() > kMaxExportNameLength)
    return Error{"export name: 1 to " + std::to_string(kMaxExportNameLength) + " characters"};
  for (const char c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                       c == '_' || c == '-';
    if (!plain) return Error{"export name: a plain file name (letters, digits, '.', '_', '-'), no directory"};
  }
  if (name.front() == '.') return Error{"export name: must not start with '.'"};
  const std::string ext = "." + format;
  if (name.size() <= ext.size() || name.compare(name.size() - ext.size(), ext.size(), ext) != 0)
    return Error{"export name: must end in " + ext + " for format " + format};
  return okStatus();
}

std::uint64_t exportBytesBound(const std::string& format, std::uint64_t cells, std::uint64_t ogfm_bytes) {
  if (format == "ogfm") return ogfm_bytes + 64 * 1024;
  std::uint64_t per_cell = 96;
  if (format == "ply" || format == "pcd") per_cell = 20;
  if (format == "bt") per_cell = 8;
  return cells * per_cell + 64 * 1024;
}

Result<ExportDirectory> ExportDirectory::open(const std::filesystem::path& dir) {
  if (::mkdir(dir.c_str(), 0750) != 0 && errno != EEXIST)
    return Error{"export directory " + dir.string() + ": cannot create (" + errnoText() + ")"};
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0)
    return Error{"export directory " + dir.string() + ": cannot open (" + errnoText() +
                 "; it must be a directory, not a symbolic link)"};
  return ExportDirectory(fd, dir);
}

ExportDirectory::ExportDirectory(ExportDirectory&& o) noexcept : fd_(o.fd_), path_(std::move(o.path_)) { o.fd_ = -1; }

ExportDirectory& ExportDirectory::operator=(ExportDirectory&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    path_ = std::move(o.path_);
    o.fd_ = -1;
  }
  return *this;
}

ExportDirectory::~ExportDirectory() {
  if (fd_ >= 0) ::close(fd_);
}

bool ExportDirectory::holds(const std::string& name) const {
  struct stat st {};
  return ::fstatat(fd_, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 || errno != ENOENT;
}

Result<std::uint64_t> ExportDirectory::freeBytes() const {
  struct statvfs vfs {};
  if (::fstatvfs(fd_, &vfs) != 0) return Error{"export directory " + path_.string() + ": statvfs: " + errnoText()};
  return static_cast<std::uint64_t>(vfs.f_bavail) * static_cast<std::uint64_t>(vfs.f_frsize);
}

Status ExportDirectory::writeNew(const std::string& name,
                                 const std::function<Status(const std::filesystem::path&)>& write) const {
  const std::string where = (path_ / name).string();
  // An unnamed file in the directory; where the file system has no O_TMPFILE, a random name nobody can
  // guess, created exclusively and without following a link.
  std::string temp_name;
  int fd = ::openat(fd_, ".", O_TMPFILE | O_WRONLY | O_CLOEXEC, 0640);
  if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
    if (sodium_init() < 0) return Error{"libsodium failed to initialise"};
    unsigned char random[16];
    randombytes_buf(random, sizeof random);
    char hex[33];
    sodium_bin2hex(hex, sizeof hex, random, sizeof random);
    temp_name = std::string(".export-") + hex + ".tmp";
    fd = ::openat(fd_, temp_name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0640);
  }
  if (fd < 0) return Error{where + ": cannot create a file in the export directory (" + errnoText() + ")"};
  const auto discard = [&] {
    ::close(fd);
    if (!temp_name.empty()) ::unlinkat(fd_, temp_name.c_str(), 0);
  };
  // The writer opens the file through its descriptor; what it names is this file, whatever the directory holds.
  if (auto st = write(procPath(fd)); !st) {
    discard();
    return Error{where + ": " + st.error().message};
  }
  if (::fsync(fd) != 0) {
    const std::string why = errnoText();
    discard();
    return Error{where + ": fsync: " + why};
  }
  // link fails with EEXIST rather than replace a file (a rename would replace it).
  const int linked = temp_name.empty()
                         ? ::linkat(AT_FDCWD, procPath(fd).c_str(), fd_, name.c_str(), AT_SYMLINK_FOLLOW)
                         : ::linkat(fd_, temp_name.c_str(), fd_, name.c_str(), 0);
  const int link_errno = errno;
  discard();
  if (linked != 0) {
    if (link_errno == EEXIST) return Error{where + ": exists; an export never replaces a file"};
    return Error{where + ": cannot name the written file (" + std::strerror(link_errno) + ")"};
  }
  ::fsync(fd_);
  return okStatus();
}

}  // namespace ogf::mapper_daemon
