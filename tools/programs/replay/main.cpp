// ogf-replay: replays a Velodyne capture (a pcap, a packets LCM log or a ROS 2 bag) onto UDP without root,
// as tcpreplay would for a driver listening on a socket: each record's UDP payload is sent to --dest at the
// data or position port, paced by the capture timestamps divided by --speed on a steady clock (sleep_until
// from the start, so no drift), with loops and a packet-rate limit; optionally the robot's odometry is
// published on LCM at the same pace, stamped on the clock ogf-driver will give the replayed packets
// (--odometry-clock, ogf/replay/odometry_clock.hpp), so ogf-driver and ogf-mapper see a live robot.
// Records that are not usable UDP are skipped and counted.
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <lcm/lcm-cpp.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/log_io/packet_log.hpp"
#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/replay/destination_ports.hpp"
#include "ogf/replay/odometry_clock.hpp"
#include "ogf/replay/pose_events.hpp"
#include "ogf/replay/replay_clock.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"

namespace {

namespace ds = ogf::driver_sources;
using Clock = std::chrono::steady_clock;

using ogf::cli::kExitOk;
constexpr int kExitNothingSent = 1;
using ogf::cli::kExitUsage;  // bad flags or configuration

struct Counts {
  std::int64_t data = 0;
  std::int64_t position = 0;
  std::int64_t other = 0;
  std::int64_t skipped = 0;      // records that are not a whole IPv4/UDP datagram
  std::int64_t send_errors = 0;  // sendto failures (counted, the replay goes on)
  std::int64_t poses = 0;
  std::int64_t pose_errors = 0;
  std::int64_t late_us_max = 0;  // worst lateness of a send behind its due time
  std::int64_t packets() const { return data + position + other; }
};

const char* kindName(ds::FrameKind k) {
  switch (k) {
    case ds::FrameKind::Udp: return "udp";
    case ds::FrameKind::NotUdp: return "not UDP";
    case ds::FrameKind::Fragment: return "IPv4 fragment";
    case ds::FrameKind::Truncated: return "truncated";
    case ds::FrameKind::UnsupportedLink: return "unsupported link type";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Replays a capture's UDP payloads (or the raw packet batches of an LCM log, or a ROS 2 bag's VelodyneScan\n"
      "packets) onto the network (no root needed), optionally with the robot's odometry "
      "on LCM on the same clock.\n"
      "Data packets (captured to 2368) go to --data-port, position packets (8308) to --position-port, others to "
      "their captured port. Pacing: capture time / --speed, on a steady clock; --fast sends as fast as possible; "
      "--max-rate caps packets per second. Each odometry pose is published when the replay clock reaches its "
      "utime (capture clock), stamped on --odometry-clock: as recorded (capture), or moved to the host time at "
      "which the replay sends what was captured then (host), which is the clock ogf-driver stamps replayed "
      "packets with when they carry no PPS-locked GPS time (auto picks it so).\n"
      "At the end one line on stdout:\n"
      "  packets N data N position N other N skipped N send_errors N poses N loops N seconds S rate R\n"
      "Exit 0 when packets were sent, 1 when none could be (an input missing or unreadable), 2 on bad flags."};
  std::string pcap, lcm_log, rosbag2, packets_topic, packets_channel = "VELODYNE_PACKETS", dest = "127.0.0.1",
      odometry, lcm_url,
      pose_channel = "POSE", log_level = "info", odometry_clock_name = "auto";
  int data_port = 2368, position_port = 8308, loops = 1;
  double speed = 1.0, max_rate = 0.0, start_delay = 0.0, loop_gap = 0.0;
  bool fast = false;
  auto* pcap_opt = app.add_option("--pcap", pcap, "Capture file (pcap or pcapng)");
  auto* log_opt = app.add_option("--lcm-log", lcm_log,
                                 "LCM log whose raw packet batches (--packets-channel) are sent as the sensor sent "
                                 "them, paced by their host receive times");
  auto* bag_opt = app.add_option("--rosbag2", rosbag2,
                                 "ROS 2 bag folder (or one .db3) whose velodyne_msgs/msg/VelodyneScan packets are sent "
                                 "to the data port, paced by their stamps");
  pcap_opt->excludes(log_opt)->excludes(bag_opt);
  log_opt->excludes(bag_opt);
  app.add_option("--packets-topic", packets_topic, "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  app.add_option("--packets-channel", packets_channel, "Channel of the raw packet batches in --lcm-log")
      ->capture_default_str();
  app.add_option("--dest", dest, "Destination IPv4 address")->capture_default_str();
  app.add_option("--data-port", data_port, "Port for data packets (captured to 2368)")
      ->capture_default_str()->check(ogf::cli::between(1, 65535));
  app.add_option("--position-port", position_port, "Port for position packets (captured to 8308)")
      ->capture_default_str()->check(ogf::cli::between(1, 65535));
  auto* speed_opt = app.add_option("--speed", speed, "Pacing factor: capture time / speed")
                        ->capture_default_str()->check(ogf::cli::positive());
  app.add_flag("--fast", fast, "As fast as possible (no pacing by the capture clock)")->excludes(speed_opt);
  app.add_option("--loop", loops, "Play the capture this many times")->capture_default_str()->check(ogf::cli::positive());
  app.add_option("--loop-gap", loop_gap, "Seconds between loops")->capture_default_str()->check(ogf::cli::nonNegative());
  app.add_option("--max-rate", max_rate, "At most this many packets per second (0: no limit)")
      ->capture_default_str()->check(ogf::cli::nonNegative());
  auto* odo_opt = app.add_option("--odometry", odometry,
                                 "Odometry to publish: CSV utime,x,y,z,qw,qx,qy,qz (as ogf.odometry_t) or an LCM log "
                                 "(events on --pose-channel, republished as they are)");
  app.add_option("--lcm-url", lcm_url, "LCM URL for the odometry (default $LCM_DEFAULT_URL, else LCM's default)")
      ->needs(odo_opt);
  app.add_option("--pose-channel", pose_channel, "Odometry channel")->capture_default_str();
  app.add_option("--odometry-clock", odometry_clock_name,
                 "Clock of the published odometry's utime: capture (as recorded), host (the host time the replay "
                 "sends the packets captured at that utime), auto (host unless the capture's position packets "
                 "carry PPS-locked GPS time, as ogf-driver and ogf-mapper's time_base auto decide)")
      ->capture_default_str()->check(CLI::IsMember({"capture", "host", "auto"}))->needs(odo_opt);
  app.add_option("--start-delay", start_delay, "Seconds to wait before the first packet (let listeners start)")
      ->capture_default_str()->check(ogf::cli::nonNegative());
  app.add_option("--log-level", log_level, "trace|debug|info|warn|error")->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (pcap.empty() && lcm_log.empty() && rosbag2.empty()) {
    std::fprintf(stderr, "ogf-replay: give --pcap FILE, --lcm-log FILE or --rosbag2 DIR\n");
    return kExitUsage;
  }
  const std::string input = !pcap.empty() ? pcap : (!lcm_log.empty() ? lcm_log : rosbag2);

  if (!ogf::transport::setupLoggingAt("ogf-replay", "--log-level", log_level)) return kExitUsage;

  // A bag: opened and its packet topic chosen before anything is sent.
  std::optional<ogf::rosbag::Rosbag2Storage> bag;
  std::string bag_topic;
  if (!rosbag2.empty()) {
    auto opened = ogf::rosbag::Rosbag2Storage::open(rosbag2);
    if (!opened) {
      spdlog::error("--rosbag2: {}", opened.error().message);
      return kExitNothingSent;
    }
    bag = std::move(*opened);
    if (const auto found = bag->whereFound(); !found.empty()) spdlog::info("{}", found);
    if (const auto others = ogf::rosbag::undecodedTopicsSummary(bag->topics()); !others.empty())
      spdlog::info("{}: not read (types ogf does not decode): {}", rosbag2, others);
    auto topic = ogf::rosbag::choosePacketTopic(*bag, packets_topic);
    if (!topic) {
      spdlog::error("--packets-topic: {}", topic.error().message);
      return kExitUsage;
    }
    if (!*topic) {
      spdlog::error("{}: no {} topic: nothing to send", rosbag2, ogf::rosbag::kVelodyneScanType);
      return kExitNothingSent;
    }
    bag_topic = **topic;
  }

  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address_v4(dest, ec);
  if (ec) {
    spdlog::error("--dest: '{}' is not an IPv4 address", dest);
    return kExitUsage;
  }
  const ogf::replay::DestinationPorts ports{static_cast<std::uint16_t>(data_port), static_cast<std::uint16_t>(position_port)};

  std::optional<ogf::replay::PoseEvents> poses;
  std::unique_ptr<lcm::LCM> lcm;
  if (!odometry.empty()) {
    auto loaded = ogf::replay::loadPoseEvents(odometry, pose_channel);
    if (!loaded) {
      spdlog::error("--odometry: {}", loaded.error().message);
      return kExitNothingSent;
    }
    for (const auto& p : loaded->problems) spdlog::warn("{}; skipped", p);
    if (loaded->skipped > static_cast<std::int64_t>(loaded->problems.size()))
      spdlog::warn("{} more malformed odometry lines skipped", loaded->skipped - static_cast<std::int64_t>(loaded->problems.size()));
    poses = std::move(*loaded);
    // Publish only: no subscription, so LCM opens no receive socket.
    const std::string url = ogf::transport::resolveLcmUrl(lcm_url);
    lcm = std::make_unique<lcm::LCM>(url);
    if (!lcm->good()) {
      spdlog::error("cannot join the LCM bus {} (udpm needs a multicast route: scripts/multicast-loopback.sh)", url);
      return kExitNothingSent;
    }
    spdlog::info("{}: {} poses to publish on {} ({})", odometry, poses->events.size(), pose_channel, url);
  }

  // The odometry's clock: auto looks at the capture's position packets first.
  const ogf::replay::OdometryClock requested_clock = *ogf::replay::parseOdometryClock(odometry_clock_name);
  ogf::replay::OdometryClock odometry_clock = ogf::replay::OdometryClock::kCapture;
  std::string clock_reason = "--odometry-clock capture";
  if (poses) {
    ogf::replay::GpsTimeProbe probe;
    if (requested_clock == ogf::replay::OdometryClock::kAuto) {
      if (!pcap.empty()) {
        if (auto reader = ds::PcapFileReader::open(pcap)) {
          ds::PcapRecord record;
          for (ds::ReadStatus st = (*reader)->next(record); !probe.decided() && st != ds::ReadStatus::End &&
                                                               st != ds::ReadStatus::Error;
               st = (*reader)->next(record))
            if (st == ds::ReadStatus::Datagram && record.datagram.destination_port == ports.kCapturedPosition)
              probe.addPositionPayload(record.datagram.payload);
        }
      } else if (!lcm_log.empty()) {
        (void)ogf::log_io::readPacketLog(lcm_log, packets_channel, [&](const ogf::log_io::LoggedPacket& p) {
          if (p.port == ports.kCapturedPosition) probe.addPositionPayload(p.payload);
        });
      }
      clock_reason = std::string("--odometry-clock auto: ") + input +
                     (probe.hasGpsTime() ? " has PPS-locked GPS time, which ogf-driver stamps the packets with"
                                         : " has no PPS-locked GPS time (" + std::to_string(probe.positionPackets()) +
                                               " position packets looked at), so ogf-driver stamps the replayed "
                                               "packets on the host clock");
    } else if (requested_clock == ogf::replay::OdometryClock::kHost) {
      clock_reason = "--odometry-clock host";
    }
    odometry_clock = ogf::replay::resolveOdometryClock(requested_clock, probe);
    if (odometry_clock == ogf::replay::OdometryClock::kHost) {
      if (fast) {
        spdlog::error("odometry on the host clock ({}) needs a paced replay: --fast gives the packets no host time "
                      "to stamp the poses with; use --speed, or --odometry-clock capture",
                      clock_reason);
        return kExitUsage;
      }
      for (const auto& e : poses->events) {
        if (auto moved = ogf::replay::restampPose(e.bytes, [](std::int64_t t) { return t; }); !moved) {
          spdlog::error("--odometry {}: {} ({}); --odometry-clock capture publishes it as recorded", odometry,
                        moved.error().message, clock_reason);
          return kExitNothingSent;
        }
      }
    }
  }

  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket(io);
  socket.open(boost::asio::ip::udp::v4(), ec);
  if (ec) {
    spdlog::error("cannot open a UDP socket: {}", ec.message());
    return kExitNothingSent;
  }
  socket.set_option(boost::asio::socket_base::send_buffer_size(4 * 1024 * 1024), ec);  // best effort

  ogf::replay::ReplayClock clock({fast ? 0.0 : speed, max_rate});
  Counts counts;
  std::string damage;
  bool origin_set = false;

  if (start_delay > 0) std::this_thread::sleep_for(std::chrono::duration<double>(start_delay));
  const Clock::time_point start = Clock::now();
  // The host time of the replay's start: a record due at offset d goes out at host time start_host_us + d.
  const std::int64_t start_host_us = std::chrono::duration_cast<std::chrono::microseconds>(
                                         std::chrono::system_clock::now().time_since_epoch())
                                         .count();
  const auto hostTimeOf = [&](std::int64_t capture_utime) { return start_host_us + clock.dueEvent(capture_utime); };
  const auto waitUntil = [&](std::int64_t due_us) {
    const auto due = start + std::chrono::microseconds(due_us);
    const auto now = Clock::now();
    if (now < due) std::this_thread::sleep_until(due);
    else counts.late_us_max = std::max<std::int64_t>(counts.late_us_max, std::chrono::duration_cast<std::chrono::microseconds>(now - due).count());
  };
  const auto publishPose = [&](const ogf::replay::PoseEvent& e) {
    const std::vector<std::uint8_t>* bytes = &e.bytes;
    ogf::Result<std::vector<std::uint8_t>> moved = std::vector<std::uint8_t>();
    if (odometry_clock == ogf::replay::OdometryClock::kHost) {
      moved = ogf::replay::restampPose(e.bytes, hostTimeOf);
      if (!moved) {
        ++counts.pose_errors;
        return;
      }
      bytes = &*moved;
    }
    if (lcm->publish(pose_channel, bytes->data(), static_cast<unsigned>(bytes->size())) == 0) ++counts.poses;
    else ++counts.pose_errors;
  };

  std::size_t next_pose = 0;
  // What a recording's reader skipped and its gaps, said once (on the first loop).
  const auto warnRecording = [&](int at_loop, const std::vector<std::string>& problems, const std::string& gaps) {
    if (at_loop > 0) return;
    for (const auto& problem : problems) spdlog::warn("{}", problem);
    if (!gaps.empty()) spdlog::warn("{}", gaps);
  };
  // One datagram as captured (its time and destination port), sent when the replay clock reaches it.
  const auto sendDatagram = [&](std::int64_t utime, int captured_port, std::span<const std::uint8_t> payload) {
    if (!origin_set) {
      std::int64_t origin = utime;
      if (poses && !poses->events.empty()) origin = std::min(origin, poses->events.front().utime);
      clock.setOrigin(origin);
      origin_set = true;
      if (poses && odometry_clock == ogf::replay::OdometryClock::kHost)
        spdlog::info("odometry on the host clock ({}): each pose's utime moves by {:+.6f} s, the replay's start on "
                     "the host clock minus the capture's start{}",
                     clock_reason, static_cast<double>(hostTimeOf(origin) - origin) / 1e6,
                     speed != 1.0 ? " (then capture time / --speed)" : "");
      else if (poses)
        spdlog::info("odometry on the capture clock ({}): poses published as recorded", clock_reason);
    }
    // Poses due before this packet go first, each at its own time.
    while (poses && next_pose < poses->events.size() && poses->events[next_pose].utime <= utime) {
      waitUntil(clock.dueEvent(poses->events[next_pose].utime));
      publishPose(poses->events[next_pose++]);
    }
    waitUntil(clock.duePacket(utime));
    const std::uint16_t port = ports.forCaptured(static_cast<std::uint16_t>(captured_port));
    socket.send_to(boost::asio::buffer(payload.data(), payload.size()), boost::asio::ip::udp::endpoint(address, port), 0, ec);
    if (ec) {
      ++counts.send_errors;
      spdlog::debug("send to {}:{} failed: {}", dest, port, ec.message());
      return;
    }
    if (captured_port == ports.kCapturedData) ++counts.data;
    else if (captured_port == ports.kCapturedPosition) ++counts.position;
    else ++counts.other;
  };

  int loop = 0;
  for (; loop < loops; ++loop) {
    if (loop > 0) clock.nextLoop(static_cast<std::int64_t>(loop_gap * 1e6));
    next_pose = 0;
    if (bag) {
      auto read = ogf::rosbag::readBagPackets(*bag, bag_topic, [&](const ogf::rosbag::BagPacket& p) {
        sendDatagram(p.host_utime, ports.kCapturedData, p.payload);
      });
      if (!read) {
        spdlog::error("--rosbag2: {}", read.error().message);
        return kExitNothingSent;
      }
      warnRecording(loop, read->problems, read->gaps.summary(rosbag2 + ": " + bag_topic + " messages"));
    } else if (!lcm_log.empty()) {
      auto read = ogf::log_io::readPacketLog(lcm_log, packets_channel, [&](const ogf::log_io::LoggedPacket& p) {
        sendDatagram(p.host_utime, p.port, p.payload);
      });
      if (!read) {
        spdlog::error("--lcm-log: {}", read.error().message);
        return kExitNothingSent;
      }
      warnRecording(loop, read->problems, read->gaps.summary(lcm_log + ": " + packets_channel + " batches"));
      if (loop == 0 && read->batches == 0) spdlog::warn("{}: no packet batches on {}", lcm_log, packets_channel);
    } else {
      auto reader = ds::PcapFileReader::open(pcap);
      if (!reader) {
        spdlog::error("--pcap: {}", reader.error().message);
        return kExitNothingSent;
      }
      ds::PcapRecord record;
      while (true) {
        const ds::ReadStatus st = (*reader)->next(record);
        if (st == ds::ReadStatus::End) break;
        if (st == ds::ReadStatus::Error) {
          damage = (*reader)->error();
          break;
        }
        if (st == ds::ReadStatus::Skipped || record.kind != ds::FrameKind::Udp) {
          ++counts.skipped;
          spdlog::debug("record {} skipped: {}", record.index, kindName(record.kind));
          continue;
        }
        sendDatagram(record.datagram.utime, record.datagram.destination_port, record.datagram.payload);
      }
    }
    // Poses after the last packet: the mapper needs the pose after a scan's end to place its last points.
    while (poses && next_pose < poses->events.size()) {
      waitUntil(clock.dueEvent(poses->events[next_pose].utime));
      publishPose(poses->events[next_pose++]);
    }
    if (!damage.empty()) break;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  if (!damage.empty()) spdlog::warn("{}: reading stopped at damage: {}; the records before it were sent", input, damage);
  if (counts.skipped > 0) spdlog::warn("{} records skipped (not a whole IPv4/UDP datagram)", counts.skipped);
  if (counts.send_errors > 0) spdlog::warn("{} datagrams could not be sent", counts.send_errors);
  if (counts.pose_errors > 0) spdlog::warn("{} poses could not be published", counts.pose_errors);
  if (!fast && counts.late_us_max > 20000)
    spdlog::warn("fell behind the capture clock by up to {:.1f} ms", static_cast<double>(counts.late_us_max) / 1000.0);
  const double rate = seconds > 0 ? static_cast<double>(counts.packets()) / seconds : 0.0;
  std::printf("packets %lld data %lld position %lld other %lld skipped %lld send_errors %lld poses %lld loops %d "
              "seconds %.3f rate %.1f\n",
              static_cast<long long>(counts.packets()), static_cast<long long>(counts.data),
              static_cast<long long>(counts.position), static_cast<long long>(counts.other),
              static_cast<long long>(counts.skipped), static_cast<long long>(counts.send_errors),
              static_cast<long long>(counts.poses), loop == loops ? loops : loop + 1, seconds, rate);
  return counts.packets() > 0 ? kExitOk : kExitNothingSent;
}
