// The shared daemon helper itself (daemon_process.hpp), on a real ogf-mapper over udpm on loopback and on
// programs that are no daemon: a status is waited for and a clean stop is seen as one, while a program that
// sends no status, one that exits first, one that does not start and one that dies of SIGTERM instead of
// exiting 0 each fail the check with the reason.
#include "support/daemon_process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/mapper_status_t.hpp>

#include <filesystem>
#include <string>

#include "support/multicast.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

std::string logPath(const std::string& name) {
  return (fs::temp_directory_path() / ("ogf-daemon-process-" + std::to_string(::getpid()) + "-" + name)).string();
}

TEST(DaemonProcess, AMapperReportsItsStatusAndExitsZeroOnSigterm) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(90);
  Mapper mapper({std::string(OGF_BIN_DIR) + "/ogf-mapper", "--lcm-url", url, "--in-memory"}, logPath("mapper.log"),
                url, ogf::testing::kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(15s));
  const auto status = mapper.latestStatus();
  ASSERT_TRUE(status);
  EXPECT_EQ(status->scans_in, 0);
  EXPECT_TRUE(mapper.running());
  EXPECT_TRUE(mapper.stop());
  EXPECT_FALSE(mapper.running());
  fs::remove(logPath("mapper.log"));
}

TEST(DaemonProcess, AProgramThatSendsNoStatusFailsTheWaitAndOneKilledBySigtermFailsTheStop) {
  const std::string url = ogf::testing::loopbackUdpmUrl(91);
  Mapper silent({"/bin/sleep", "30"}, logPath("sleep.log"), url, ogf::testing::kMapperStatusChannel);
  const auto waited = silent.reportsStatus(300ms);
  EXPECT_FALSE(waited);
  EXPECT_NE(std::string(waited.message()).find("no status within 300 ms"), std::string::npos) << waited.message();
  const auto stopped = silent.stop();  // sleep does not handle SIGTERM: it dies of it, status -15
  EXPECT_FALSE(stopped);
  EXPECT_NE(std::string(stopped.message()).find("exited with -15 after SIGTERM"), std::string::npos)
      << stopped.message();
  fs::remove(logPath("sleep.log"));
}

TEST(DaemonProcess, AProgramThatExitsBeforeAnyStatusFailsTheWaitWithItsExitStatus) {
  const std::string url = ogf::testing::loopbackUdpmUrl(93);
  Mapper exits({"/bin/false"}, logPath("false.log"), url, ogf::testing::kMapperStatusChannel);
  const auto waited = exits.reportsStatus(15s);
  EXPECT_FALSE(waited);
  EXPECT_NE(std::string(waited.message()).find("(it exited with 1)"), std::string::npos) << waited.message();
  fs::remove(logPath("false.log"));
}

TEST(DaemonProcess, AProgramThatDoesNotStartFailsTheWaitAndAKilledOneIsGone) {
  const std::string url = ogf::testing::loopbackUdpmUrl(92);
  Mapper missing({"/nonexistent/ogf-mapper"}, logPath("missing.log"), url, ogf::testing::kMapperStatusChannel);
  const auto waited = missing.reportsStatus(100ms);
  EXPECT_FALSE(waited);
  EXPECT_NE(std::string(waited.message()).find("did not start"), std::string::npos) << waited.message();
  Mapper sleeper({"/bin/sleep", "30"}, logPath("sleep2.log"), url, ogf::testing::kMapperStatusChannel);
  EXPECT_TRUE(sleeper.running());
  EXPECT_TRUE(sleeper.kill());
  EXPECT_FALSE(sleeper.running());
  fs::remove(logPath("missing.log"));
  fs::remove(logPath("sleep2.log"));
}

}  // namespace
