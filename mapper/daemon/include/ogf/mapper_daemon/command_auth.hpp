// Authentication of map commands (OGF_MAP_COMMAND): a message authentication code made with a key shared
// by ogf-mapper and whoever may command it (ogf-map-query --key), and a guard against replays.
// The MAC is libsodium's crypto_auth (HMAC-SHA-512-256) over the LCM encoding of the command with its mac
// field zeroed, so it covers every field. The key file holds the 32-byte key as 64 hexadecimal digits; it
// must be a regular file owned by the reading user and readable by nobody else (mode 0600 or 0400).
#pragma once

#include <ogf/map_command_t.hpp>

#include <array>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf::mapper_daemon {

struct CommandKey {
  std::array<unsigned char, 32> bytes{};
};

// Reads and checks a key file (regular, not a symbolic link, owned by this user, no group or other
// permission bits, 64 hex digits); the error names the file and what is wrong.
Result<CommandKey> loadCommandKey(const std::filesystem::path& path);

// Creates a new key file with a random key, mode 0600; never replaces an existing file.
Status createCommandKey(const std::filesystem::path& path);

// Sets c.mac for the key (the other fields as they are).
void signCommand(ogf::map_command_t& c, const CommandKey& key);

// Whether c.mac is the key's MAC of c (compared in constant time).
bool commandMacValid(const ogf::map_command_t& c, const CommandKey& key);

// The replay rule: a command is fresh when its utime is within `window_us` of the receiver's clock, not
// before `not_before_utime` (the receiver's start: commands recorded before a restart stay refused) and its
// mac is not among those accepted within the window. Only authenticated commands are offered to it, so
// only the key's holder can fill the list of accepted macs; beyond kMaxRemembered within one window the
// newest is refused as a replay (never forgotten early).
class ReplayGuard {
 public:
  static constexpr std::size_t kMaxRemembered = 4096;
  enum class Verdict { kFresh, kOutsideWindow, kBeforeStart, kReplayed };

  ReplayGuard(std::int64_t not_before_utime, std::int64_t window_us);
  // Records the command as accepted when fresh.
  Verdict admit(const ogf::map_command_t& c, std::int64_t now_utime);

 private:
  struct Seen {
    std::int64_t utime;
    std::array<std::int8_t, 32> mac;
  };
  std::int64_t not_before_;
  std::int64_t window_us_;
  std::deque<Seen> seen_;
};

}  // namespace ogf::mapper_daemon
