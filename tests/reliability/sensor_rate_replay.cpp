#include "sensor_rate_replay.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "integration/scan_feeder.hpp"
#include "programs.hpp"
#include "support/daemon_process.hpp"
#include "support/lcm_thread.hpp"
#include "support/multicast.hpp"
#include "support/process_memory.hpp"

namespace ogf::testing {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const ogf::source_status_t* sourceOn(const ogf::mapper_status_t& s, const std::string& channel) {
  for (const auto& src : s.sources)
    if (src.scan_channel == channel) return &src;
  return nullptr;
}

// The delta messages' arrival times, from an LCM thread.
struct DeltaTimes {
  std::mutex mu;
  std::vector<Clock::time_point> at;
  void on(const lcm::ReceiveBuffer*, const std::string&) {
    std::lock_guard lk(mu);
    at.push_back(Clock::now());
  }
};

}  // namespace

ReplayFigures replayAtSensorRate(const SensorRateReplay& run) {
  ReplayFigures f;
  const auto config = run.dir / (run.name + ".yaml");
  std::ofstream(config) << "status_interval_s: 0.1\n" << run.config;
  DeltaTimes times;
  LcmThread deltas(run.url);
  deltas.lcm().subscribe("OGF_MAP_DELTA", &DeltaTimes::on, &times);
  deltas.start(10ms);
  DaemonProcess<ogf::mapper_status_t> mapper(
      {binDir() + "/ogf-mapper", "--lcm-url", run.url, "--state-dir", (run.dir / ("state-" + run.name)).string(),
       "--config", config.string(), "--log-level", "warn"},
      (run.dir / ("mapper-" + run.name + ".log")).string(), run.url, kMapperStatusChannel);
  EXPECT_TRUE(mapper.reportsStatus(10s));
  RssSampler rss(mapper.process().pid(), 20ms);
  const auto first_scan = Clock::now() + 300ms;
  pid_t attacker = -1;
  if (run.attack) {
    attacker = ::fork();
    if (attacker == 0) {
      lcm::LCM bus(run.url);
      run.attack(bus, first_scan);
      ::_exit(0);
    }
  }
  lcm::LCM lcm(run.url);
  for (int i = 0; i < run.scans; ++i) {
    const auto step = feedStep(i, run.points);
    std::this_thread::sleep_until(first_scan + i * 100ms);
    for (const auto& p : step.poses) lcm.publish(run.pose_channel, &p);
    lcm.publish(run.scan_channel, &step.scan);
  }
  const auto done = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) {
        const auto* src = sourceOn(s, run.scan_channel);
        return src != nullptr && src->scans_in == run.scans &&
               src->scans_mapped + src->scans_dropped_behind + src->scans_dropped_no_pose + src->scans_late +
                       src->scans_rejected + src->scans_refused_time + src->scans_throttled ==
                   run.scans;
      },
      60s);
  const auto last_scan = Clock::now();
  if (attacker > 0) {
    ::kill(attacker, SIGKILL);
    ::waitpid(attacker, nullptr, 0);
  }
  EXPECT_TRUE(done) << run.name << ": not every scan was accounted for\n" << mapper.log();
  if (done) {
    f.status = *done;
    f.source = *sourceOn(*done, run.scan_channel);
  }
  f.first_rss_bytes = rss.firstBytes();
  f.peak_rss_bytes = rss.peakBytes();
  {
    std::lock_guard lk(times.mu);
    std::vector<Clock::time_point> in;
    for (const auto& t : times.at)
      if (t >= first_scan && t <= last_scan) in.push_back(t);
    f.deltas = static_cast<std::int64_t>(in.size());
    for (std::size_t i = 1; i < in.size(); ++i)
      f.largest_gap_s = std::max(f.largest_gap_s, std::chrono::duration<double>(in[i] - in[i - 1]).count());
  }
  EXPECT_TRUE(mapper.stop(60s)) << run.name;
  return f;
}

std::string figuresLine(const std::string& label, const ReplayFigures& f) {
  long long throttled = 0;
  for (const auto& src : f.status.sources) throttled += src.scans_throttled;
  char line[512];
  std::snprintf(line, sizeof line,
                "[ figures  ] %-14s scans mapped %lld, dropped behind %lld; %lld deltas, largest gap %.3f s; "
                "RSS %.1f MB first, %.1f MB peak; service requests %lld, refused %lld; all sources: scans in %lld, "
                "mapped %lld, throttled %lld, cells %lld",
                label.c_str(), static_cast<long long>(f.source.scans_mapped),
                static_cast<long long>(f.source.scans_dropped_behind), static_cast<long long>(f.deltas),
                f.largest_gap_s, static_cast<double>(f.first_rss_bytes) / 1e6,
                static_cast<double>(f.peak_rss_bytes) / 1e6, static_cast<long long>(f.status.service_requests_in),
                static_cast<long long>(f.status.service_requests_refused), static_cast<long long>(f.status.scans_in),
                static_cast<long long>(f.status.scans_mapped), throttled,
                static_cast<long long>(f.status.cells));
  return line;
}

}  // namespace ogf::testing
