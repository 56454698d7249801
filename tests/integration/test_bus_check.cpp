// ogf-bus-check, the first thing to run when LCM seems not to work: over real UDP multicast on loopback it
// sends one message of every type the daemons publish or read, on its own channels, and gets each back. The
// message set is read from messages/lcmtypes, so a type added there without a probe fails here. When the
// bus's port is held by a socket that does not share it, it and the programs that receive say so and exit.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "support/file_text.hpp"
#include "support/child_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

const std::string kBin = OGF_BIN_DIR;
const fs::path kLcmTypes = OGF_LCMTYPES_DIR;

// The struct names of the ogf message set that travel on a channel of their own: those no other type holds
// as a member (source_status_t only travels inside mapper_status_t).
std::set<std::string> channelTypes() {
  std::set<std::string> declared;
  std::string all;
  const std::regex struct_re(R"(struct\s+(\w+))");
  for (const auto& entry : fs::directory_iterator(kLcmTypes)) {
    if (entry.path().extension() != ".lcm") continue;
    const std::string text = ogf::testing::fileText(entry.path());
    all += text;
    for (std::sregex_iterator it(text.begin(), text.end(), struct_re), end; it != end; ++it) declared.insert((*it)[1]);
  }
  std::set<std::string> out;
  for (const std::string& type : declared) {
    const std::regex member_re("\\n\\s*" + type + "\\s+\\w+");
    if (!std::regex_search(all, member_re)) out.insert(type);
  }
  return out;
}

TEST(BusCheck, EveryMessageTypeMakesTheRoundTripOverMulticast) {
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-bus-check");
  const std::set<std::string> types = channelTypes();
  ASSERT_GE(types.size(), 12u) << "the message set read from " << kLcmTypes;
  ogf::testing::ChildProcess check({kBin + "/ogf-bus-check", "--lcm-url", ogf::testing::loopbackUdpmUrl(106),
                                    "--timeout", "10"},
                                   (dir / "bus_check.log").string());
  const auto rc = check.wait(60s);
  ASSERT_TRUE(rc.has_value());
  const std::string out = check.log();
  EXPECT_EQ(*rc, 0) << out;
  for (const std::string& type : types) {
    const std::regex row("\\n\\S+\\s+" + type + "\\s+0x[0-9a-f]{16}\\s+\\d+\\s+ok\\n");
    EXPECT_TRUE(std::regex_search(out, row)) << type << " is not in the table, or did not come back:\n" << out;
  }
  EXPECT_NE(out.find(" received, 0 missing"), std::string::npos) << out;
}

// A UDP socket bound to `port` on every address without SO_REUSEADDR, as the kernel binds a sending socket.
class HeldPort {
 public:
  explicit HeldPort(int port) : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {
    sockaddr_in at{};
    at.sin_family = AF_INET;
    at.sin_addr.s_addr = htonl(INADDR_ANY);
    at.sin_port = htons(static_cast<std::uint16_t>(port));
    bound_ = fd_ >= 0 && ::bind(fd_, reinterpret_cast<const sockaddr*>(&at), sizeof at) == 0;
  }
  ~HeldPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  HeldPort(const HeldPort&) = delete;
  HeldPort& operator=(const HeldPort&) = delete;
  bool bound() const { return bound_; }

 private:
  int fd_;
  bool bound_ = false;
};

TEST(BusCheck, AProgramWhoseBusPortIsHeldUnsharedSaysSoAndExits) {
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-bus-held");
  const std::string url = ogf::testing::loopbackUdpmUrl(107);
  const std::regex port_re(R"(:(\d+)\?)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(url, m, port_re)) << url;
  HeldPort held(std::stoi(m[1]));
  ASSERT_TRUE(held.bound()) << "port " << m[1] << " is in use";
  const std::vector<std::vector<std::string>> programs{
      {kBin + "/ogf-bus-check", "--lcm-url", url, "--timeout", "5"},
      {kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory"},
      {kBin + "/ogf-map-client", "--lcm-url", url, "--duration", "5"},
      {kBin + "/ogf-view", "--lcm-url", url, "--port", "0"},
      {kBin + "/ogf-map-query", "--lcm-url", url, "--timeout", "5", "sources"},
  };
  int n = 0;
  for (const auto& argv : programs) {
    SCOPED_TRACE(argv.front());
    ogf::testing::ChildProcess program(argv, (dir / ("program" + std::to_string(++n) + ".log")).string());
    const auto rc = program.wait(30s);
    ASSERT_TRUE(rc.has_value()) << "still running: " << program.log();
    EXPECT_GT(*rc, 0) << "an exit with an error, not success nor a signal: " << program.log();
    EXPECT_NE(program.log().find("cannot receive on the LCM bus " + url), std::string::npos) << program.log();
  }
  fs::remove_all(dir);
}

}  // namespace
