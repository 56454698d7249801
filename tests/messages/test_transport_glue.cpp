// The pieces of transport glue that need no network: URL resolution, the receive-buffer option, the
// systemd notification datagrams, and the log rate limiter.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <filesystem>
#include <string>

#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/sd_notify.hpp"

namespace {

using namespace ogf::transport;

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) ::setenv(name, value, 1); else ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) ::setenv(name_, old_->c_str(), 1); else ::unsetenv(name_);
  }
 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(LcmUrl, FlagWinsOverEnvironment) {
  ScopedEnv env("LCM_DEFAULT_URL", "udpm://239.255.76.67:7000?ttl=1");
  EXPECT_EQ(resolveLcmUrl("memq://"), "memq://");
}

TEST(LcmUrl, EnvironmentUsedWithoutFlag) {
  ScopedEnv env("LCM_DEFAULT_URL", "udpm://239.255.76.67:7000?ttl=1");
  EXPECT_EQ(resolveLcmUrl(""), "udpm://239.255.76.67:7000?ttl=1");
}

TEST(LcmUrl, LcmDefaultWithoutFlagOrEnvironment) {
  ScopedEnv env("LCM_DEFAULT_URL", nullptr);
  EXPECT_EQ(resolveLcmUrl(""), "udpm://239.255.76.67:7667?ttl=0");
  ScopedEnv empty("LCM_DEFAULT_URL", "");
  EXPECT_EQ(resolveLcmUrl(""), "udpm://239.255.76.67:7667?ttl=0");
}

TEST(LcmUrl, ReceiveBufferAddedOnlyToUdpmWithoutOne) {
  EXPECT_EQ(withReceiveBuffer("udpm://239.255.76.67:7667", 100), "udpm://239.255.76.67:7667?recv_buf_size=100");
  EXPECT_EQ(withReceiveBuffer("udpm://239.255.76.67:7667?ttl=1", 100),
            "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=100");
  EXPECT_EQ(withReceiveBuffer("udpm://239.255.76.67:7667?recv_buf_size=5&ttl=1", 100),
            "udpm://239.255.76.67:7667?recv_buf_size=5&ttl=1");
  EXPECT_EQ(withReceiveBuffer("udpm://239.255.76.67:7667?ttl=1&recv_buf_size=5", 100),
            "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=5");
  EXPECT_EQ(withReceiveBuffer("memq://", 100), "memq://");
  EXPECT_EQ(withReceiveBuffer("file:///tmp/x.log?mode=w", 100), "file:///tmp/x.log?mode=w");
}

// A fake systemd: a datagram socket NOTIFY_SOCKET points at.
class FakeSystemd {
 public:
  explicit FakeSystemd(bool abstract) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    const std::string name = "ogf-test-notify-" + std::to_string(::getpid()) + (abstract ? "-a" : "-p");
    if (abstract) {
      path_ = "@" + name;
      std::memcpy(addr.sun_path + 1, name.data(), name.size());
      ::bind(fd_, reinterpret_cast<sockaddr*>(&addr),
             static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + 1 + name.size()));
    } else {
      path_ = (std::filesystem::temp_directory_path() / name).string();
      std::filesystem::remove(path_);
      std::memcpy(addr.sun_path, path_.data(), path_.size());
      ::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
      file_ = path_;
    }
    timeval tv{1, 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  }
  ~FakeSystemd() {
    ::close(fd_);
    if (!file_.empty()) std::filesystem::remove(file_);
  }
  const std::string& path() const { return path_; }
  std::string receive() {
    char buf[512];
    const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  }
 private:
  int fd_ = -1;
  std::string path_;
  std::string file_;
};

TEST(SystemdNotifier, SilentWithoutNotifySocket) {
  ScopedEnv env("NOTIFY_SOCKET", nullptr);
  SystemdNotifier n;
  EXPECT_FALSE(n.enabled());
  EXPECT_FALSE(n.ready());
}

TEST(SystemdNotifier, SendsStatesToPathSocket) {
  FakeSystemd systemd(false);
  ScopedEnv env("NOTIFY_SOCKET", systemd.path().c_str());
  SystemdNotifier n;
  ASSERT_TRUE(n.enabled());
  EXPECT_TRUE(n.ready("mapping"));
  EXPECT_EQ(systemd.receive(), "READY=1\nSTATUS=mapping");
  EXPECT_TRUE(n.watchdog());
  EXPECT_EQ(systemd.receive(), "WATCHDOG=1");
  EXPECT_TRUE(n.stopping());
  EXPECT_EQ(systemd.receive(), "STOPPING=1");
}

TEST(SystemdNotifier, SendsToAbstractSocket) {
  FakeSystemd systemd(true);
  ScopedEnv env("NOTIFY_SOCKET", systemd.path().c_str());
  SystemdNotifier n;
  EXPECT_TRUE(n.ready());
  EXPECT_EQ(systemd.receive(), "READY=1");
}

TEST(SystemdNotifier, WatchdogOnlyForOurPid) {
  ScopedEnv usec("WATCHDOG_USEC", "5000000");
  {
    ScopedEnv pid("WATCHDOG_PID", std::to_string(::getpid()).c_str());
    SystemdNotifier n;
    ASSERT_TRUE(n.watchdogInterval().has_value());
    EXPECT_EQ(n.watchdogInterval()->count(), 5000000);
  }
  {
    ScopedEnv pid("WATCHDOG_PID", "1");
    EXPECT_FALSE(SystemdNotifier().watchdogInterval().has_value());
  }
  {
    ScopedEnv pid("WATCHDOG_PID", nullptr);
    EXPECT_TRUE(SystemdNotifier().watchdogInterval().has_value());
  }
}

TEST(LogRateLimiter, AllowsOncePerPeriodAndCountsTheRest) {
  LogRateLimiter limiter(std::chrono::seconds(1));
  const auto t0 = std::chrono::steady_clock::time_point{} + std::chrono::hours(1);
  EXPECT_EQ(limiter.allow(t0), std::optional<std::uint64_t>(0));
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(limiter.allow(t0 + std::chrono::milliseconds(90 * i)));
  EXPECT_EQ(limiter.allow(t0 + std::chrono::seconds(2)), std::optional<std::uint64_t>(10));
  EXPECT_EQ(limiter.allow(t0 + std::chrono::seconds(4)), std::optional<std::uint64_t>(0));
}

TEST(Logging, ParsesLevelNames) {
  EXPECT_EQ(parseLogLevel("debug"), spdlog::level::debug);
  EXPECT_EQ(parseLogLevel("warn"), spdlog::level::warn);
  EXPECT_EQ(parseLogLevel("error"), spdlog::level::err);
  EXPECT_FALSE(parseLogLevel("loud").has_value());
}

TEST(Logging, AnUnknownLevelIsRefusedNamingProgramAndOption) {
  ::testing::internal::CaptureStderr();
  EXPECT_FALSE(setupLoggingAt("ogf-test", "--log-level", "loud"));
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("ogf-test: --log-level: unknown level 'loud'"), std::string::npos) << said;
  EXPECT_TRUE(setupLoggingAt("ogf-test", "--log-level", "warn"));
  EXPECT_EQ(spdlog::default_logger()->name(), "ogf-test");
  EXPECT_EQ(spdlog::default_logger()->level(), spdlog::level::warn);
}

}  // namespace
