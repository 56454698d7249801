// ogf-bus-check, the first thing to run when LCM seems not to work: over real UDP multicast on loopback it
// sends one message of every type the daemons publish or read, on its own channels, and gets each back. The
// message set is read from messages/lcmtypes, so a type added there without a probe fails here.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "support/child_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

const std::string kBin = OGF_BIN_DIR;
const fs::path kLcmTypes = OGF_LCMTYPES_DIR;

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The struct names of the ogf message set that travel on a channel of their own: those no other type holds
// as a member (source_status_t only travels inside mapper_status_t).
std::set<std::string> channelTypes() {
  std::set<std::string> declared;
  std::string all;
  const std::regex struct_re(R"(struct\s+(\w+))");
  for (const auto& entry : fs::directory_iterator(kLcmTypes)) {
    if (entry.path().extension() != ".lcm") continue;
    const std::string text = readFile(entry.path());
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

}  // namespace
