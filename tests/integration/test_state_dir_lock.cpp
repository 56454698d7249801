// One ogf-mapper per state directory, as real processes: a second mapper on the same directory refuses
// to start, naming the directory and the first one's pid; after kill -9 of the first, a new mapper starts
// on it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/mapper_status_t.hpp>

#include <filesystem>
#include <fstream>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

const std::string kBin = OGF_BIN_DIR;

TEST(StateDirectoryLock, SecondMapperRefusedKillNineReleases) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-lock-it");
  std::ofstream(dir / "mapper.yaml") << "status_interval_s: 0.1\n";
  const std::string url = ogf::testing::loopbackUdpmUrl(224);
  const fs::path state = dir / "state";
  const auto mapperArgs = [&](const std::string& status_channel) {
    return std::vector<std::string>{kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", state.string(), "--config",
                                    (dir / "mapper.yaml").string(), "--status-channel", status_channel};
  };
  Mapper first(mapperArgs("FIRST_STATUS"), (dir / "first.log").string(), url, "FIRST_STATUS");
  ASSERT_TRUE(first.reportsStatus(15s));

  ChildProcess second(mapperArgs("SECOND_STATUS"), (dir / "second.log").string());
  const auto rc = second.wait(15s);
  ASSERT_TRUE(rc.has_value()) << "the second mapper must not run\n" << second.log();
  EXPECT_EQ(*rc, 1);
  EXPECT_NE(second.log().find(state.string() + " is in use by process " + std::to_string(first.process().pid())),
            std::string::npos)
      << second.log();
  EXPECT_TRUE(first.running()) << "the first mapper runs on";

  ASSERT_TRUE(first.kill());
  Mapper third(mapperArgs("THIRD_STATUS"), (dir / "third.log").string(), url, "THIRD_STATUS");
  ASSERT_TRUE(third.reportsStatus(15s));
  EXPECT_TRUE(third.stop());
  fs::remove_all(dir);
}

}  // namespace
