// Map command authentication: see command_auth.hpp.
#include "ogf/mapper_daemon/command_auth.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace ogf::mapper_daemon {
namespace {

static_assert(crypto_auth_KEYBYTES == 32 && crypto_auth_BYTES == 32, "map_command_t.mac holds crypto_auth's 32 bytes");

bool sodiumReady() {
  static const bool ready = sodium_init() >= 0;
  return ready;
}

std::vector<std::uint8_t> macInput(const ogf::map_command_t& c) {
  ogf::map_command_t zeroed = c;
  std::fill(std::begin(zeroed.mac), std::end(zeroed.mac), std::int8_t{0});
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(zeroed.getEncodedSize()));
  zeroed.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

Result<CommandKey> loadCommandKey(const std::filesystem::path& path) {
  const std::string name = "key file " + path.string();
  Fd fd(::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK));
  if (fd.get() < 0) return Error::configuration(name + ": cannot open (" + std::strerror(errno) + "; a symbolic link is refused)");
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) return Error::configuration(name + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return Error::configuration(name + ": not a regular file");
  if (st.st_uid != ::geteuid())
    return Error::configuration(name + ": owned by uid " + std::to_string(st.st_uid) + ", not by this user (uid " +
                 std::to_string(::geteuid()) + ")");
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    return Error::configuration(name + ": mode " + mode + " lets the group or others read it; chmod 600 it");
  }
  char text[130] = {};
  const auto n = ::read(fd.get(), text, sizeof text - 1);
  if (n < 0) return Error::configuration(name + ": " + std::strerror(errno));
  std::string hex(text, static_cast<std::size_t>(n));
  while (!hex.empty() && (hex.back() == '\n' || hex.back() == '\r' || hex.back() == ' ')) hex.pop_back();
  if (!sodiumReady()) return Error::internal("libsodium failed to initialise");
  CommandKey key;
  std::size_t len = 0;
  if (hex.size() != 64 || sodium_hex2bin(key.bytes.data(), key.bytes.size(), hex.data(), hex.size(), nullptr, &len,
                                         nullptr) != 0 || len != 32)
    return Error::configuration(name + ": expected 64 hexadecimal digits (a 32-byte key; ogf-map-query keygen FILE makes one)");
  return key;
}

Status createCommandKey(const std::filesystem::path& path) {
  if (!sodiumReady()) return Error::internal("libsodium failed to initialise");
  Fd fd(::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600));
  if (fd.get() < 0) return Error{kindOfErrno(errno), path.string() + ": cannot create (" + std::strerror(errno) + "); an existing file is never replaced"};
  CommandKey key;
  crypto_auth_keygen(key.bytes.data());
  char hex[65];
  sodium_bin2hex(hex, sizeof hex, key.bytes.data(), key.bytes.size());
  sodium_memzero(key.bytes.data(), key.bytes.size());
  std::string line = std::string(hex, 64) + "\n";
  sodium_memzero(hex, sizeof hex);
  const bool ok = ::write(fd.get(), line.data(), line.size()) == static_cast<ssize_t>(line.size()) && ::fsync(fd.get()) == 0;
  sodium_memzero(line.data(), line.size());
  if (!ok) return Error{kindOfErrno(errno), path.string() + ": write failed (" + std::strerror(errno) + ")"};
  return okStatus();
}

void signCommand(ogf::map_command_t& c, const CommandKey& key) {
  (void)sodiumReady();
  const auto bytes = macInput(c);
  unsigned char mac[crypto_auth_BYTES];
  crypto_auth(mac, bytes.data(), bytes.size(), key.bytes.data());
  std::memcpy(c.mac, mac, sizeof mac);
}

bool commandMacValid(const ogf::map_command_t& c, const CommandKey& key) {
  if (!sodiumReady()) return false;
  const auto bytes = macInput(c);
  unsigned char mac[crypto_auth_BYTES];
  std::memcpy(mac, c.mac, sizeof mac);
  return crypto_auth_verify(mac, bytes.data(), bytes.size(), key.bytes.data()) == 0;
}

ReplayGuard::ReplayGuard(std::int64_t not_before_utime, std::int64_t window_us)
    : not_before_(not_before_utime), window_us_(window_us) {}

ReplayGuard::Verdict ReplayGuard::admit(const ogf::map_command_t& c, std::int64_t now_utime) {
  if (c.utime > now_utime + window_us_ || c.utime < now_utime - window_us_) return Verdict::kOutsideWindow;
  if (c.utime < not_before_) return Verdict::kBeforeStart;
  // Macs of commands that left the window can be forgotten: their commands are refused by time.
  while (!seen_.empty() && seen_.front().utime < now_utime - window_us_) seen_.pop_front();
  std::array<std::int8_t, 32> mac{};
  std::memcpy(mac.data(), c.mac, mac.size());
  for (const Seen& s : seen_) {
    if (s.mac == mac) return Verdict::kReplayed;
  }
  if (seen_.size() >= kMaxRemembered) return Verdict::kReplayed;
  // Kept ordered by utime (commands arrive roughly in order), so the front is always the oldest.
  const auto at = std::upper_bound(seen_.begin(), seen_.end(), c.utime,
                                   [](std::int64_t u, const Seen& s) { return u < s.utime; });
  seen_.insert(at, Seen{c.utime, mac});
  return Verdict::kFresh;
}

}  // namespace ogf::mapper_daemon
