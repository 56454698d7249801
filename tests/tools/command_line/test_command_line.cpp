// ogf::cli::parseCommandLine: the exit-code convention, unknown options named before missing required
// ones, and value checks that state the rule.
#include <gtest/gtest.h>

#include <sstream>
#include <vector>

#include "ogf/common/command_line.hpp"

namespace {

struct Captured {
  std::optional<int> rc;
  std::string err;
};

Captured run(std::vector<const char*> args) {
  CLI::App app{"test", "prog"};
  std::string pcap;
  double resolution = 0.2, angle = 0;
  app.add_option("--pcap", pcap, "input")->required();
  app.add_option("--resolution", resolution, "cell")->check(ogf::cli::positive());
  app.add_option("--cut-angle", angle, "deg")->check(ogf::cli::between(-360, 360));
  args.insert(args.begin(), "prog");
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  Captured c;
  c.rc = ogf::cli::parseCommandLine(app, static_cast<int>(args.size()), args.data());
  std::cerr.rdbuf(old);
  c.err = err.str();
  return c;
}

TEST(CommandLine, GoodArgumentsGoOn) { EXPECT_EQ(run({"--pcap", "x", "--resolution", "0.1"}).rc, std::nullopt); }

TEST(CommandLine, MistypedRequiredFlagIsAnUnknownOption) {
  const auto c = run({"--pcapp", "x"});
  EXPECT_EQ(c.rc, ogf::cli::kExitUsage);
  EXPECT_NE(c.err.find("unknown option --pcapp (did you mean --pcap?)"), std::string::npos) << c.err;
  EXPECT_EQ(c.err.find("required"), std::string::npos) << c.err;
}

TEST(CommandLine, NegativeValueSaysTheRuleInWords) {
  const auto c = run({"--pcap", "x", "--resolution", "-1"});
  EXPECT_EQ(c.rc, ogf::cli::kExitUsage);
  EXPECT_NE(c.err.find("must be greater than 0, got -1"), std::string::npos) << c.err;
  EXPECT_LT(c.err.size(), 200u) << c.err;
}

TEST(CommandLine, BadValueIsReportedBeforeAMissingRequiredOption) {
  const auto c = run({"--resolution", "-1"});
  EXPECT_EQ(c.rc, ogf::cli::kExitUsage);
  EXPECT_NE(c.err.find("prog: --resolution: must be greater than 0, got -1"), std::string::npos) << c.err;
  const auto missing = run({"--resolution", "1"});
  EXPECT_NE(missing.err.find("--pcap is required"), std::string::npos) << missing.err;
}

TEST(CommandLine, OutOfRangeAngle) {
  const auto c = run({"--pcap", "x", "--cut-angle", "400"});
  EXPECT_EQ(c.rc, ogf::cli::kExitUsage);
  EXPECT_NE(c.err.find("must be between -360 and 360, got 400"), std::string::npos) << c.err;
}

TEST(CommandLine, NotANumber) {
  const auto c = run({"--pcap", "x", "--resolution", "abc"});
  EXPECT_EQ(c.rc, ogf::cli::kExitUsage);
  EXPECT_NE(c.err.find("--resolution"), std::string::npos) << c.err;
}

TEST(CommandLine, MissingRequiredIsUsage) { EXPECT_EQ(run({}).rc, ogf::cli::kExitUsage); }

TEST(CommandLine, HelpIsSuccess) { EXPECT_EQ(run({"--help"}).rc, ogf::cli::kExitOk); }

}  // namespace
