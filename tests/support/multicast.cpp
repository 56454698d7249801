#include "support/multicast.hpp"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

namespace ogf::testing {

namespace {

constexpr int kFirstTestPort = 20000;

std::string run(const char* cmd) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd, "r"), ::pclose);
  if (!pipe) return out;
  std::array<char, 256> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe.get()) != nullptr) out += buf.data();
  return out;
}

bool routesOverLoopback() {
  const std::string route = run("ip route get 239.255.76.67 2>/dev/null");
  return route.find(" dev lo") != std::string::npos;
}

// The lowest port the kernel hands to a socket bound to none (Linux's default 32768).
int firstEphemeralPort() {
  std::ifstream in("/proc/sys/net/ipv4/ip_local_port_range");
  int low = 0;
  return in >> low && low > kFirstTestPort + 256 ? low : 32768;
}

}  // namespace

std::optional<std::string> ensureLoopbackMulticast() {
  if (routesOverLoopback()) return std::nullopt;
  if (::geteuid() != 0) {
    return "no multicast route over lo and not root to add one (run: ip link set lo multicast on; "
           "ip route add 224.0.0.0/4 dev lo)";
  }
  (void)std::system("ip link set lo multicast on 2>/dev/null");
  (void)std::system("ip route replace 224.0.0.0/4 dev lo 2>/dev/null");
  if (routesOverLoopback()) return std::nullopt;
  return "could not add a multicast route over lo (is iproute2 installed? is this a network namespace "
         "without CAP_NET_ADMIN?)";
}

std::string loopbackUdpmUrl(int slot) {
  // 256 ports per process, the slot's one among them: two test processes running side by side (their pids
  // a few apart) never share a port. All below the kernel's ephemeral ports: every LCM process's send
  // socket is bound to one of those, without sharing it, and a udpm URL on the same port cannot be joined.
  static const int processes = (firstEphemeralPort() - kFirstTestPort) / 256;
  const int port = kFirstTestPort + static_cast<int>(::getpid() % processes) * 256 + (slot & 255);
  return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0&recv_buf_size=8388608";
}

}  // namespace ogf::testing
