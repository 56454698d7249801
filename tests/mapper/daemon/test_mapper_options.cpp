// The mapping programs' configuration schema: --print-config's YAML holds every key of the table and reads
// back to the options it was printed from; values land in MapperOptions; older spellings are refused with
// the new name; unknown keys and bad values are named with file, line and key; the table of keys in docs/configuration.md
// is the schema's.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ogf/mapper_daemon/mapper_options.hpp"

namespace {

using ogf::mapper_daemon::MapperOptions;
using ogf::mapper_daemon::mapperConfigMarkdown;
using ogf::mapper_daemon::mapperConfigYaml;
using ogf::mapper_daemon::parseMapperOptions;
using ogf::mapper_daemon::PoseSource;

std::string errorOf(const std::string& yaml) {
  MapperOptions o;
  const auto st = parseMapperOptions(yaml, "m.yaml", o);
  return st ? "loaded" : st.error().message;
}

// The key column of the Markdown table, in order.
std::vector<std::string> tableKeys(const std::string& table) {
  std::vector<std::string> keys;
  std::istringstream in(table);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const auto end = line.find('`', 3);
    keys.push_back(line.substr(3, end - 3));
  }
  return keys;
}

TEST(MapperOptionsSchema, PrintedDefaultsHoldEveryKeyOfTheTableAndReadBackToTheDefaults) {
  const std::string printed = mapperConfigYaml();
  MapperOptions read;
  std::vector<std::string> keys;
  const auto st = parseMapperOptions(printed, "printed.yaml", read, &keys);
  ASSERT_TRUE(st.ok()) << st.error().message << "\n" << printed;
  const auto table = tableKeys(mapperConfigMarkdown());
  EXPECT_GT(table.size(), 40u);
  std::istringstream rows(mapperConfigMarkdown());
  for (std::string row; std::getline(rows, row);)
    EXPECT_EQ(std::count(row.begin(), row.end(), '|'), 6) << "a table row of five columns: " << row;
  EXPECT_EQ(keys, table) << printed;
  EXPECT_EQ(mapperConfigYaml(read), printed);
  const MapperOptions d;
  EXPECT_EQ(read.map.filter.resolution, d.map.filter.resolution);
  EXPECT_EQ(read.map.fusion.measurement.max_range_m, d.map.fusion.measurement.max_range_m);
  EXPECT_FALSE(read.map.filter.kernelSigma.has_value());
  EXPECT_EQ(read.time_base, d.time_base);
  EXPECT_EQ(read.pose_source, PoseSource::kOdometry);
  EXPECT_TRUE(read.state_dir.empty());
  EXPECT_TRUE(read.validate().ok());
}

TEST(MapperOptionsSchema, PrintedNonDefaultValuesReadBackToTheSameOptions) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("lcm_url: \"udpm://239.255.76.67:7668?ttl=1\"\nstate_dir: /var/lib/ogf map\n"
                                 "time_base: host\npose_source: static\n"
                                 "static_pose: {translation: [1, 2.5, 0], quaternion: [0, 0, 0, 1]}\n"
                                 "channels: {scan: SCANS}\nmap: {resolution: 0.1, extrinsic: {rpy: [0, 0.1, 3]}}\n"
                                 "filter: {sigma: 0.07, stencil_manhattan_radius: 0, covariance: banded}\n"
                                 "fusion: {max_pose_jump: {rotation_rad: 0.25}}\n",
                                 "m.yaml", o)
                  .ok());
  const std::string printed = mapperConfigYaml(o);
  MapperOptions again;
  const auto st = parseMapperOptions(printed, "printed.yaml", again);
  ASSERT_TRUE(st.ok()) << st.error().message << "\n" << printed;
  EXPECT_EQ(mapperConfigYaml(again), printed);
  EXPECT_EQ(again.lcm_url, "udpm://239.255.76.67:7668?ttl=1");
  EXPECT_EQ(again.state_dir, "/var/lib/ogf map");
  EXPECT_EQ(again.scan_channel, "SCANS");
  EXPECT_EQ(again.map.filter.resolution, 0.1);
  EXPECT_EQ(again.map.fusion.extrinsic.rpy_rad.z(), 3.0);
  EXPECT_EQ(*again.map.filter.kernelSigma, 0.07);
  EXPECT_EQ(again.map.filter.stencilManhattanRadius, 0);
  EXPECT_EQ(again.map.fusion.pose_buffer.jump_rotation_rad, 0.25);
  EXPECT_EQ(again.pose_source, PoseSource::kStatic);
  ASSERT_TRUE(again.static_pose.quaternion.has_value());
  EXPECT_EQ(again.static_pose.quaternion->z(), 1.0);
  EXPECT_EQ(again.static_pose.translation_m.y(), 2.5);
}

TEST(MapperOptionsSchema, ResolutionSetsFusionAndFilterAlike) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("map:\n  resolution: 0.05\n", "m.yaml", o).ok());
  EXPECT_EQ(o.map.filter.resolution, 0.05);
  EXPECT_EQ(o.map.fusion.measurement.resolution_m, 0.05);
}

TEST(MapperOptionsSchema, EveryKeyOfTheFlatDialectIsRefusedNamingItsNewName) {
  const std::pair<const char*, const char*> renamed[] = {
      {"resolution: 0.1\n", "m.yaml:1: resolution: not a key here: use map.resolution"},
      {"min_range: 0.5\n", "m.yaml:1: min_range: not a key here: use map.min_range"},
      {"max_range: 20\n", "m.yaml:1: max_range: not a key here: use map.max_range"},
      {"free_space_for_no_return: true\n", "use map.free_space_for_no_return"},
      {"extrinsic: {translation: [0, 0, 1]}\n", "m.yaml:1: extrinsic: not a key here: use map.extrinsic"},
      {"filter:\n  threads: 2\n  kernel_sigma: 0.1\n", "m.yaml:3: filter.kernel_sigma: not a key here: use filter.sigma"},
      {"filter:\n  kernel_amplitude: 4\n", "m.yaml:2: filter.kernel_amplitude: not a key here: use filter.amplitude"},
  };
  for (const auto& [yaml, expected] : renamed) {
    const std::string e = errorOf(yaml);
    EXPECT_NE(e.find(expected), std::string::npos) << yaml << " -> " << e;
  }
  // The keys the flat dialect shares with the schema keep their meaning.
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("filter:\n  stencil_radius: 2\n  stencil_manhattan_radius: 3\n  taper_support: 2.5\n",
                                 "m.yaml", o)
                  .ok());
  EXPECT_EQ(*o.map.filter.stencilRadius, 2.0);
  EXPECT_EQ(o.map.filter.stencilManhattanRadius, 3);
  EXPECT_EQ(*o.map.filter.taperSupport, 2.5);
}

TEST(MapperOptionsSchema, UnknownKeysAndBadValuesAreNamedWithFileLineAndKey) {
  EXPECT_NE(errorOf("map:\n  resolutoin: 0.5\n").find("m.yaml:2: map.resolutoin: unknown key"), std::string::npos);
  EXPECT_NE(errorOf("filter:\n  treads: 2\n").find("m.yaml:2: filter.treads: unknown key"), std::string::npos);
  EXPECT_NE(errorOf("map:\n  max_range: far\n").find("m.yaml:2: map.max_range: cannot read 'far'"), std::string::npos);
  EXPECT_NE(errorOf("map:\n  resolution: -1\n").find("m.yaml:2: map.resolution: must be greater than 0"),
            std::string::npos);
  EXPECT_NE(errorOf("filter: {threads: 0}\n").find("m.yaml:1: filter.threads: must be from 1"), std::string::npos);
  EXPECT_NE(errorOf("filter: {free_release_scans: 2.5}\n").find("filter.free_release_scans: cannot read '2.5'"),
            std::string::npos);
  EXPECT_NE(errorOf("time_base: gps\n").find("m.yaml:1: time_base: expected one of 'auto', 'device', 'host', got 'gps'"),
            std::string::npos);
  EXPECT_NE(errorOf("pose_source: tripod\n").find("pose_source: expected one of 'odometry', 'static'"), std::string::npos);
  EXPECT_NE(errorOf("static_pose:\n  translation: [0, 0]\n").find("m.yaml:2: static_pose.translation: expected [x, y, z]"),
            std::string::npos);
  EXPECT_NE(errorOf("map:\n  extrinsic: {xyz: [0, 0, 1]}\n").find("m.yaml:2: map.extrinsic.xyz: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf("channels: {query: " + std::string(60, 'Q') + "}\n").find("channels.query: must be 1 to 57"),
            std::string::npos);
  EXPECT_NE(errorOf("filter: {sigma: .nan}\n").find("filter.sigma: must be a finite number"), std::string::npos);
}

TEST(MapperOptionsSchema, StaticPoseSourceLandsInTheOptionsAndRefusesPoseCorrection) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions("pose_source: static\nstatic_pose: {translation: [1, 2, 3], rpy: [0, 0, 1.5]}\n",
                                 "m.yaml", o)
                  .ok());
  EXPECT_EQ(o.pose_source, PoseSource::kStatic);
  EXPECT_EQ(o.static_pose.translation_m.z(), 3.0);
  EXPECT_EQ(o.static_pose.rpy_rad.z(), 1.5);
  EXPECT_TRUE(o.validate().ok());
  ASSERT_TRUE(parseMapperOptions("pose_correction: {mode: rbpf}\n", "m.yaml", o).ok());
  const auto st = o.validate();
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("pose_source: odometry"), std::string::npos) << st.error().message;
}

TEST(MapperOptionsSchema, StateDirDefaultSaysStateDirectoryInThePrintAndTheTable) {
  const std::string printed = mapperConfigYaml();
  const auto line = printed.substr(printed.find("\nstate_dir:") + 1);
  EXPECT_NE(line.substr(0, line.find('\n')).find("$STATE_DIRECTORY"), std::string::npos) << printed;
  const std::string table = mapperConfigMarkdown();
  const auto row = table.substr(table.find("| `state_dir`"));
  EXPECT_NE(row.substr(0, row.find('\n')).find("`$STATE_DIRECTORY`"), std::string::npos) << table;
}

// The table of keys in docs/configuration.md lies between two markers; the test fails when it differs from the schema,
// and says how to make it again.
TEST(MapperOptionsSchema, TheConfigurationDocsTableIsTheSchemas) {
  std::ifstream in(OGF_CONFIGURATION_DOC_PATH);
  ASSERT_TRUE(in) << OGF_CONFIGURATION_DOC_PATH;
  std::stringstream text;
  text << in.rdbuf();
  const std::string readme = text.str();
  const std::string begin = "<!-- ogf-mapper --print-config=markdown -->\n";
  const std::string end = "<!-- end of ogf-mapper --print-config=markdown -->";
  const auto from = readme.find(begin);
  ASSERT_NE(from, std::string::npos) << "docs/configuration.md has no line " << begin;
  const auto to = readme.find(end, from);
  ASSERT_NE(to, std::string::npos) << "docs/configuration.md has no line " << end;
  const std::string in_readme = readme.substr(from + begin.size(), to - from - begin.size());
  EXPECT_EQ(in_readme, mapperConfigMarkdown())
      << "docs/configuration.md's table of keys differs from the schema: replace the lines between the markers with the "
         "output of build/bin/ogf-mapper --print-config=markdown";
}

}  // namespace
