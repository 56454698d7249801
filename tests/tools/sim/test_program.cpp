// ogf-sim as a process: the interface flags and file names, refusals that name the line and field, and an
// odometry drift preset that bends odometry.csv while trajectory_true.csv stays the same.
#include <gtest/gtest.h>
#include "sim_test_paths.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct ProgramRun {
  int exit_code = -1;
  std::string stderr_text;
};

class SimProgram : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ogf::sim::test::scratchPath("program_" +
                                       std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  ProgramRun run(const std::string& args) const {
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = std::string(OGF_SIM_BINARY) + " " + args + " >/dev/null 2>" + err.string();
    const int status = std::system(cmd.c_str());
    std::ifstream in(err);
    return ProgramRun{WIFEXITED(status) ? WEXITSTATUS(status) : -1,
               std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>())};
  }

  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }

  fs::path dir_;
};

TEST_F(SimProgram, WritesEveryInterfaceFileAndExitsZero) {
  const fs::path out = dir_ / "out";
  const ProgramRun r = run("--world lab --trajectory corridor --duration 0.2 --rpm 1200 --return-mode dual --seed 3 --out " +
                    out.string());
  ASSERT_EQ(r.exit_code, 0) << r.stderr_text;
  for (const char* f : {"capture.pcap", "odometry.csv", "odometry.lcmlog", "trajectory_true.csv", "truth.grid"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
    EXPECT_GT(fs::file_size(out / f), 0u) << f;
  }
  std::ifstream csv(out / "odometry.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "utime,x,y,z,qw,qx,qy,qz");
}

TEST_F(SimProgram, MalformedSceneFileIsRefusedWithLineAndField) {
  write("bad.yaml",
        "name: bad\n"
        "ground: {height: 0}\n"
        "solids:\n"
        "  - {type: box, center: [0, 0, 1], size: [1, 1, 1]}\n"
        "  - {type: cylinder, center: [1, 1], radius: -2, z: [0, 1]}\n");
  const ProgramRun r = run("--world " + (dir_ / "bad.yaml").string() + " --out " + (dir_ / "out").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.stderr_text.find("bad.yaml:5: solids[1].radius: must be positive"), std::string::npos)
      << r.stderr_text;
}

TEST_F(SimProgram, TrajectoryFileDrivesTheBody) {
  write("path.yaml", "speed: 0.5\nwaypoints: [[2.5, 3.0], [7.5, 3.0]]\n");
  const fs::path out = dir_ / "out";
  const ProgramRun r = run("--trajectory " + (dir_ / "path.yaml").string() + " --duration 0.1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.stderr_text;
  std::ifstream csv(out / "trajectory_true.csv");
  std::string line;
  std::getline(csv, line);
  std::getline(csv, line);
  EXPECT_EQ(line.substr(0, line.find(',', line.find(',') + 1)), "1704110400000000,2.500000") << line;
}

TEST_F(SimProgram, UnknownWorldAndReturnModeAreRefused) {
  ProgramRun r = run("--world moon --out " + (dir_ / "out").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.stderr_text.find("no world preset named 'moon'"), std::string::npos) << r.stderr_text;
  r = run("--return-mode both --out " + (dir_ / "out").string());
  EXPECT_NE(r.exit_code, 0);
}

// The last row of a pose CSV (utime,x,y,z,qw,qx,qy,qz) as its utime and heading (yaw, radians).
std::pair<double, double> lastStampAndYaw(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  std::istringstream row(last);
  std::vector<double> v;
  for (std::string field; std::getline(row, field, ',');) v.push_back(std::stod(field));
  if (v.size() != 8) return {0.0, 0.0};
  const double qw = v[4], qx = v[5], qy = v[6], qz = v[7];
  return {v[0], std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))};
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_F(SimProgram, OdometryDriftPresetBendsTheOdometryButNotTheTruth) {
  const std::string common = "--world lab --trajectory corridor --duration 1 --rpm 1200 --seed 3 --out ";
  const ProgramRun exact = run(common + (dir_ / "none").string());
  ASSERT_EQ(exact.exit_code, 0) << exact.stderr_text;
  const ProgramRun drift = run("--odometry-drift gyro-bias " + common + (dir_ / "gyro").string());
  ASSERT_EQ(drift.exit_code, 0) << drift.stderr_text;

  EXPECT_EQ(slurp(dir_ / "none" / "trajectory_true.csv"), slurp(dir_ / "gyro" / "trajectory_true.csv"));
  EXPECT_EQ(slurp(dir_ / "none" / "odometry.csv"), slurp(dir_ / "none" / "trajectory_true.csv"));
  EXPECT_NE(slurp(dir_ / "gyro" / "odometry.csv"), slurp(dir_ / "gyro" / "trajectory_true.csv"));
  // gyro-bias: 0.0035 rad/s of heading error, so 0.0035 * t at the last sample (CSV keeps 9 decimals).
  const auto [t_odom, yaw_odom] = lastStampAndYaw(dir_ / "gyro" / "odometry.csv");
  const auto [t_true, yaw_true] = lastStampAndYaw(dir_ / "gyro" / "trajectory_true.csv");
  ASSERT_EQ(t_odom, t_true);
  const double seconds = (t_true - 1704110400000000.0) * 1e-6;
  ASSERT_GT(seconds, 0.9);
  EXPECT_NEAR(yaw_odom - yaw_true, 0.0035 * seconds, 1e-6);
}

TEST_F(SimProgram, UnknownDriftPresetIsRefusedListingThePresets) {
  const ProgramRun r = run("--odometry-drift sideways --duration 0.1 --out " + (dir_ / "out").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.stderr_text.find("slip-and-bias"), std::string::npos) << r.stderr_text;
}

// The first line of `path`'s sensor_to_body, as sim.yaml writes it.
std::string sensorToBody(const fs::path& sim_yaml) {
  std::ifstream in(sim_yaml);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("sensor_to_body:", 0) == 0) return line;
  return "";
}

std::string fileText(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(SimProgram, ARigWritesAFolderASensorEachWithItsMountAndTheSameOdometry) {
  const fs::path out = dir_ / "rig";
  const ProgramRun r = run("--rig front-rear --duration 0.3 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.stderr_text;
  for (const char* sensor : {"front", "rear"})
    for (const char* f : {"capture.pcap", "odometry.csv", "truth.grid", "sim.yaml"})
      EXPECT_TRUE(fs::exists(out / sensor / f)) << sensor << "/" << f;
  EXPECT_EQ(sensorToBody(out / "front" / "sim.yaml"), "sensor_to_body: {xyz: [0.5, 0, 0.4], quaternion_wxyz: [1, 0, 0, 0]}");
  EXPECT_NE(sensorToBody(out / "rear" / "sim.yaml").find("xyz: [-0.5, 0, 1.4]"), std::string::npos);
  EXPECT_EQ(fileText(out / "front" / "odometry.csv"), fileText(out / "rear" / "odometry.csv"));
  EXPECT_NE(fileText(out / "front" / "capture.pcap"), fileText(out / "rear" / "capture.pcap"));
  const std::string listing = fileText(out / "rig.yaml");
  EXPECT_NE(listing.find("{name: front, folder: front,"), std::string::npos) << listing;
  EXPECT_NE(listing.find("{name: rear, folder: rear,"), std::string::npos) << listing;
}

TEST_F(SimProgram, RobotsDriveTheWorldsTrajectoriesEachIntoItsOwnFolder) {
  const fs::path out = dir_ / "robots";
  const ProgramRun r = run("--robots 2 --duration 0.3 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.stderr_text;
  EXPECT_NE(fileText(out / "robot1" / "sim.yaml").find("trajectory: loop"), std::string::npos);
  EXPECT_NE(fileText(out / "robot2" / "sim.yaml").find("trajectory: corridor"), std::string::npos);
  EXPECT_NE(fileText(out / "robot1" / "odometry.csv"), fileText(out / "robot2" / "odometry.csv"));
  EXPECT_NE(fileText(out / "robots.yaml").find("{name: robot2, folder: robot2, trajectory: corridor,"), std::string::npos);
  const ProgramRun both = run("--robots 2 --trajectory loop --out " + (dir_ / "x").string());
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.stderr_text.find("--trajectory: each of --robots drives one of the world's trajectories"), std::string::npos)
      << both.stderr_text;
}

}  // namespace
