// The daemons' configuration parsers on malformed YAML: every file is either loaded or refused with an
// error naming the file and line; none throws (an exception out of start-up would end the program with
// std::terminate instead of the clear error and exit code 2 systemd shows). These inputs threw before the
// parsers caught every YAML exception (a non-scalar key or a value of the wrong kind outside the per-key
// reads); the fuzz target tests/fuzz/config searches for more.
#include <gtest/gtest.h>

#include <string>

#include "driver_config.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"

namespace {

std::string mapperError(const std::string& yaml) {
  ogf::mapper_daemon::MapperOptions o;
  const auto st = ogf::mapper_daemon::parseMapperOptions(yaml, "m.yaml", o);
  return st ? "loaded" : st.error().message;
}

std::string driverError(const std::string& yaml) {
  const auto c = ogf::driver::parseDriverConfig(yaml, "d.yaml", {});
  return c ? "loaded" : c.error().message;
}

TEST(ConfigBadInput, MapperOptionsRefuseMalformedYamlWithTheFileAndLine) {
  EXPECT_EQ(mapperError(""), "loaded");
  EXPECT_EQ(mapperError("status_interval_s: 0.1\n"), "loaded");
  for (const char* bad : {"time_base: [device]\n", "[a, b]: 1\n", "map: {extrinsic: {quaternion: [1, x, 0, 0]}}\n",
                          "? {a: 1}\n: 2\n", "fusion:\n  max_pending_points: -3e99\n", "map: [1, 2]\n", "{\n",
                          "status_interval_s: [\n", "channels: {scan: {x: 1}}\n"}) {
    const std::string e = mapperError(bad);
    EXPECT_NE(e, "loaded") << bad;
    EXPECT_EQ(e.rfind("m.yaml:", 0), 0u) << bad << " -> " << e;
  }
}

TEST(ConfigBadInput, DriverConfigRefusesMalformedYamlWithTheFileAndLine) {
  EXPECT_EQ(driverError(""), "loaded");
  EXPECT_EQ(driverError("data_port: 2368\n"), "loaded");
  for (const char* bad : {"[a]: 1\n", "? {x: 1}\n: 2\n", "data_port: [1]\n", "source: {a: b}\n", "- 1\n- 2\n", "{\n",
                          "min_range: 1e999x\n"}) {
    const std::string e = driverError(bad);
    EXPECT_NE(e, "loaded") << bad;
    EXPECT_EQ(e.rfind("d.yaml", 0), 0u) << bad << " -> " << e;
  }
}

}  // namespace
