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
#include "ogf/replay/replay_counts.hpp"
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

// A step that cannot go on returns the exit code (after logging why); nullopt goes on.
using Stop = std::optional<int>;

const char* const kDescription =
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
    "Exit 0 when packets were sent, 1 when none could be (an input missing or unreadable), 2 on bad flags.";

struct Options {
  std::string pcap, lcm_log, rosbag2, packets_topic, packets_channel = "VELODYNE_PACKETS", dest = "127.0.0.1",
      odometry, lcm_url, pose_channel = "POSE", log_level = "info", odometry_clock_name = "auto";
  int data_port = 2368, position_port = 8308, loops = 1;
  double speed = 1.0, max_rate = 0.0, start_delay = 0.0, loop_gap = 0.0;
  bool fast = false;

  // The capture's name in messages: whichever of --pcap, --lcm-log and --rosbag2 was given.
  const std::string& input() const { return !pcap.empty() ? pcap : (!lcm_log.empty() ? lcm_log : rosbag2); }
};

void addOptions(CLI::App& app, Options& o) {
  auto* pcap_opt = app.add_option("--pcap", o.pcap, "Capture file (pcap or pcapng)");
  auto* log_opt = app.add_option("--lcm-log", o.lcm_log,
                                 "LCM log whose raw packet batches (--packets-channel) are sent as the sensor sent "
                                 "them, paced by their host receive times");
  auto* bag_opt = app.add_option("--rosbag2", o.rosbag2,
                                 "ROS 2 bag folder (sqlite3 or MCAP), or one .db3 or .mcap file, whose "
                                 "velodyne_msgs/msg/VelodyneScan packets are sent "
                                 "to the data port, paced by their stamps");
  pcap_opt->excludes(log_opt)->excludes(bag_opt);
  log_opt->excludes(bag_opt);
  app.add_option("--packets-topic", o.packets_topic, "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  app.add_option("--packets-channel", o.packets_channel, "Channel of the raw packet batches in --lcm-log")
      ->capture_default_str();
  app.add_option("--dest", o.dest, "Destination IPv4 address")->capture_default_str();
  app.add_option("--data-port", o.data_port, "Port for data packets (captured to 2368)")
      ->capture_default_str()->check(ogf::cli::between(1, 65535));
  app.add_option("--position-port", o.position_port, "Port for position packets (captured to 8308)")
      ->capture_default_str()->check(ogf::cli::between(1, 65535));
  auto* speed_opt = app.add_option("--speed", o.speed, "Pacing factor: capture time / speed")
                        ->capture_default_str()->check(ogf::cli::positive());
  app.add_flag("--fast", o.fast, "As fast as possible (no pacing by the capture clock)")->excludes(speed_opt);
  app.add_option("--loop", o.loops, "Play the capture this many times")->capture_default_str()->check(ogf::cli::positive());
  app.add_option("--loop-gap", o.loop_gap, "Seconds between loops")->capture_default_str()->check(ogf::cli::nonNegative());
  app.add_option("--max-rate", o.max_rate, "At most this many packets per second (0: no limit)")
      ->capture_default_str()->check(ogf::cli::nonNegative());
  auto* odo_opt = app.add_option("--odometry", o.odometry,
                                 "Odometry to publish: CSV utime,x,y,z,qw,qx,qy,qz (as ogf.odometry_t) or an LCM log "
                                 "(events on --pose-channel, republished as they are)");
  app.add_option("--lcm-url", o.lcm_url, "LCM URL for the odometry (default $LCM_DEFAULT_URL, else LCM's default)")
      ->needs(odo_opt);
  app.add_option("--pose-channel", o.pose_channel, "Odometry channel")->capture_default_str();
  app.add_option("--odometry-clock", o.odometry_clock_name,
                 "Clock of the published odometry's utime: capture (as recorded), host (the host time the replay "
                 "sends the packets captured at that utime), auto (host unless the capture's position packets "
                 "carry PPS-locked GPS time, as ogf-driver and ogf-mapper's time_base auto decide)")
      ->capture_default_str()->check(CLI::IsMember({"capture", "host", "auto"}))->needs(odo_opt);
  app.add_option("--start-delay", o.start_delay, "Seconds to wait before the first packet (let listeners start)")
      ->capture_default_str()->check(ogf::cli::nonNegative());
  app.add_option("--log-level", o.log_level, "trace|debug|info|warn|error")->capture_default_str();
}

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

// A bag, opened and its packet topic chosen before anything is sent.
struct Bag {
  std::optional<ogf::rosbag::Rosbag2Storage> storage;
  std::string topic;
};

Stop openBag(const Options& o, Bag& bag) {
  if (o.rosbag2.empty()) return std::nullopt;
  auto opened = ogf::rosbag::Rosbag2Storage::open(o.rosbag2);
  if (!opened) {
    spdlog::error("--rosbag2: {}", opened.error().message);
    return kExitNothingSent;
  }
  bag.storage = std::move(*opened);
  if (const auto found = bag.storage->whereFound(); !found.empty()) spdlog::info("{}", found);
  if (const auto others = ogf::rosbag::undecodedTopicsSummary(bag.storage->topics()); !others.empty())
    spdlog::info("{}: not read (types ogf does not decode): {}", o.rosbag2, others);
  auto topic = ogf::rosbag::choosePacketTopic(*bag.storage, o.packets_topic);
  if (!topic) {
    spdlog::error("--packets-topic: {}", topic.error().message);
    return kExitUsage;
  }
  if (!*topic) {
    spdlog::error("{}: no {} topic: nothing to send", o.rosbag2, ogf::rosbag::kVelodyneScanType);
    return kExitNothingSent;
  }
  bag.topic = **topic;
  return std::nullopt;
}

struct Destination {
  boost::asio::ip::address_v4 address;
  ogf::replay::DestinationPorts ports;
};

Stop resolveDestination(const Options& o, Destination& destination) {
  boost::system::error_code ec;
  destination.address = boost::asio::ip::make_address_v4(o.dest, ec);
  if (ec) {
    spdlog::error("--dest: '{}' is not an IPv4 address", o.dest);
    return kExitUsage;
  }
  destination.ports = {static_cast<std::uint16_t>(o.data_port), static_cast<std::uint16_t>(o.position_port)};
  return std::nullopt;
}

// The odometry published beside the packets, the bus it goes on and the clock it is stamped on.
struct Odometry {
  std::optional<ogf::replay::PoseEvents> poses;
  std::unique_ptr<lcm::LCM> lcm;
  ogf::replay::OdometryClock clock = ogf::replay::OdometryClock::kCapture;
  std::string clock_reason = "--odometry-clock capture";
};

Stop loadOdometry(const Options& o, Odometry& odometry) {
  if (o.odometry.empty()) return std::nullopt;
  auto loaded = ogf::replay::loadPoseEvents(o.odometry, o.pose_channel);
  if (!loaded) {
    spdlog::error("--odometry: {}", loaded.error().message);
    return kExitNothingSent;
  }
  for (const auto& p : loaded->problems) spdlog::warn("{}; skipped", p);
  if (loaded->skipped > static_cast<std::int64_t>(loaded->problems.size()))
    spdlog::warn("{} more malformed odometry lines skipped", loaded->skipped - static_cast<std::int64_t>(loaded->problems.size()));
  odometry.poses = std::move(*loaded);
  // Publish only: no subscription, so LCM opens no receive socket.
  const std::string url = ogf::transport::resolveLcmUrl(o.lcm_url);
  odometry.lcm = std::make_unique<lcm::LCM>(url);
  if (!odometry.lcm->good()) {
    spdlog::error("cannot join the LCM bus {} (udpm needs a multicast route: scripts/multicast-loopback.sh)", url);
    return kExitNothingSent;
  }
  spdlog::info("{}: {} poses to publish on {} ({})", o.odometry, odometry.poses->events.size(), o.pose_channel, url);
  return std::nullopt;
}

// The capture's position packets, looked at for PPS-locked GPS time (a bag has none to look at).
ogf::replay::GpsTimeProbe probeCapture(const Options& o) {
  ogf::replay::GpsTimeProbe probe;
  constexpr auto kPosition = ogf::replay::DestinationPorts::kCapturedPosition;
  if (!o.pcap.empty()) {
    if (auto reader = ds::PcapFileReader::open(o.pcap)) {
      ds::PcapRecord record;
      for (ds::ReadStatus st = (*reader)->next(record); !probe.decided() && st != ds::ReadStatus::End &&
                                                           st != ds::ReadStatus::Error;
           st = (*reader)->next(record))
        if (st == ds::ReadStatus::Datagram && record.datagram.destination_port == kPosition)
          probe.addPositionPayload(record.datagram.payload);
    }
  } else if (!o.lcm_log.empty()) {
    (void)ogf::log_io::readPacketLog(o.lcm_log, o.packets_channel, [&](const ogf::log_io::LoggedPacket& p) {
      if (p.port == kPosition) probe.addPositionPayload(p.payload);
    });
  }
  return probe;
}

// The odometry's clock: auto looks at the capture's position packets first. On the host clock every pose
// must be one the replay can restamp, and the replay must be paced.
Stop chooseOdometryClock(const Options& o, Odometry& odometry) {
  if (!odometry.poses) return std::nullopt;
  const ogf::replay::OdometryClock requested = *ogf::replay::parseOdometryClock(o.odometry_clock_name);
  ogf::replay::GpsTimeProbe probe;
  if (requested == ogf::replay::OdometryClock::kAuto) probe = probeCapture(o);
  odometry.clock_reason = ogf::replay::odometryClockReason(requested, o.input(), probe);
  odometry.clock = ogf::replay::resolveOdometryClock(requested, probe);
  if (odometry.clock != ogf::replay::OdometryClock::kHost) return std::nullopt;
  if (o.fast) {
    spdlog::error("odometry on the host clock ({}) needs a paced replay: --fast gives the packets no host time "
                  "to stamp the poses with; use --speed, or --odometry-clock capture",
                  odometry.clock_reason);
    return kExitUsage;
  }
  for (const auto& e : odometry.poses->events) {
    if (auto moved = ogf::replay::restampPose(e.bytes, [](std::int64_t t) { return t; }); !moved) {
      spdlog::error("--odometry {}: {} ({}); --odometry-clock capture publishes it as recorded", o.odometry,
                    moved.error().message, odometry.clock_reason);
      return kExitNothingSent;
    }
  }
  return std::nullopt;
}

Stop openSocket(boost::asio::ip::udp::socket& socket) {
  boost::system::error_code ec;
  socket.open(boost::asio::ip::udp::v4(), ec);
  if (ec) {
    spdlog::error("cannot open a UDP socket: {}", ec.message());
    return kExitNothingSent;
  }
  socket.set_option(boost::asio::socket_base::send_buffer_size(4 * 1024 * 1024), ec);  // best effort
  return std::nullopt;
}

// Sends the datagrams and publishes the poses, each when the replay clock reaches it.
class Replayer {
 public:
  Replayer(const Options& o, const Destination& destination, Odometry& odometry, boost::asio::ip::udp::socket& socket)
      : o_(o), destination_(destination), odometry_(odometry), socket_(socket),
        clock_({o.fast ? 0.0 : o.speed, o.max_rate}) {}

  // The start of the replay, after --start-delay.
  void start() {
    if (o_.start_delay > 0) std::this_thread::sleep_for(std::chrono::duration<double>(o_.start_delay));
    start_ = Clock::now();
    // The host time of the replay's start: a record due at offset d goes out at host time start_host_us + d.
    start_host_us_ = std::chrono::duration_cast<std::chrono::microseconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count();
  }

  void beginLoop(int loop) {
    if (loop > 0) clock_.nextLoop(static_cast<std::int64_t>(o_.loop_gap * 1e6));
    next_pose_ = 0;
  }

  // One datagram as captured (its time and destination port), sent when the replay clock reaches it.
  void sendDatagram(std::int64_t utime, int captured_port, std::span<const std::uint8_t> payload) {
    if (!origin_set_) setOrigin(utime);
    // Poses due before this packet go first, each at its own time.
    while (hasPoses() && next_pose_ < odometry_.poses->events.size() && odometry_.poses->events[next_pose_].utime <= utime)
      publishNextPose();
    waitUntil(clock_.duePacket(utime));
    const std::uint16_t port = destination_.ports.forCaptured(static_cast<std::uint16_t>(captured_port));
    boost::system::error_code ec;
    socket_.send_to(boost::asio::buffer(payload.data(), payload.size()),
                    boost::asio::ip::udp::endpoint(destination_.address, port), 0, ec);
    if (ec) {
      ++counts_.send_errors;
      spdlog::debug("send to {}:{} failed: {}", o_.dest, port, ec.message());
      return;
    }
    if (captured_port == destination_.ports.kCapturedData) ++counts_.data;
    else if (captured_port == destination_.ports.kCapturedPosition) ++counts_.position;
    else ++counts_.other;
  }

  // Poses after the last packet: the mapper needs the pose after a scan's end to place its last points.
  void publishRemainingPoses() {
    while (hasPoses() && next_pose_ < odometry_.poses->events.size()) publishNextPose();
  }

  void countSkipped() { ++counts_.skipped; }
  const ogf::replay::ReplayCounts& counts() const { return counts_; }
  double secondsSinceStart() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  bool hasPoses() const { return odometry_.poses.has_value(); }
  std::int64_t hostTimeOf(std::int64_t capture_utime) const { return start_host_us_ + clock_.dueEvent(capture_utime); }

  void setOrigin(std::int64_t utime) {
    std::int64_t origin = utime;
    if (hasPoses() && !odometry_.poses->events.empty()) origin = std::min(origin, odometry_.poses->events.front().utime);
    clock_.setOrigin(origin);
    origin_set_ = true;
    if (hasPoses() && odometry_.clock == ogf::replay::OdometryClock::kHost)
      spdlog::info("odometry on the host clock ({}): each pose's utime moves by {:+.6f} s, the replay's start on "
                   "the host clock minus the capture's start{}",
                   odometry_.clock_reason, static_cast<double>(hostTimeOf(origin) - origin) / 1e6,
                   o_.speed != 1.0 ? " (then capture time / --speed)" : "");
    else if (hasPoses())
      spdlog::info("odometry on the capture clock ({}): poses published as recorded", odometry_.clock_reason);
  }

  void waitUntil(std::int64_t due_us) {
    const auto due = start_ + std::chrono::microseconds(due_us);
    const auto now = Clock::now();
    if (now < due) std::this_thread::sleep_until(due);
    else counts_.late_us_max = std::max<std::int64_t>(counts_.late_us_max, std::chrono::duration_cast<std::chrono::microseconds>(now - due).count());
  }

  void publishNextPose() {
    const ogf::replay::PoseEvent& e = odometry_.poses->events[next_pose_++];
    waitUntil(clock_.dueEvent(e.utime));
    const std::vector<std::uint8_t>* bytes = &e.bytes;
    ogf::Result<std::vector<std::uint8_t>> moved = std::vector<std::uint8_t>();
    if (odometry_.clock == ogf::replay::OdometryClock::kHost) {
      moved = ogf::replay::restampPose(e.bytes, [this](std::int64_t t) { return hostTimeOf(t); });
      if (!moved) {
        ++counts_.pose_errors;
        return;
      }
      bytes = &*moved;
    }
    if (odometry_.lcm->publish(o_.pose_channel, bytes->data(), static_cast<unsigned>(bytes->size())) == 0) ++counts_.poses;
    else ++counts_.pose_errors;
  }

  const Options& o_;
  const Destination& destination_;
  Odometry& odometry_;
  boost::asio::ip::udp::socket& socket_;
  ogf::replay::ReplayClock clock_;
  ogf::replay::ReplayCounts counts_;
  Clock::time_point start_;
  std::int64_t start_host_us_ = 0;
  bool origin_set_ = false;
  std::size_t next_pose_ = 0;
};

// What a recording's reader skipped and its gaps, said once (on the first loop).
void warnRecording(int loop, const std::vector<std::string>& problems, const std::string& gaps) {
  if (loop > 0) return;
  for (const auto& problem : problems) spdlog::warn("{}", problem);
  if (!gaps.empty()) spdlog::warn("{}", gaps);
}

// One pass over the capture; `damage` says where a damaged pcap stopped the reading.
Stop playOnce(const Options& o, const Bag& bag, int loop, Replayer& replayer, std::string& damage) {
  constexpr auto kData = ogf::replay::DestinationPorts::kCapturedData;
  if (bag.storage) {
    auto read = ogf::rosbag::readBagPackets(*bag.storage, bag.topic, [&](const ogf::rosbag::BagPacket& p) {
      replayer.sendDatagram(p.host_utime, kData, p.payload);
    });
    if (!read) {
      spdlog::error("--rosbag2: {}", read.error().message);
      return kExitNothingSent;
    }
    warnRecording(loop, read->problems, read->gaps.summary(o.rosbag2 + ": " + bag.topic + " messages"));
  } else if (!o.lcm_log.empty()) {
    auto read = ogf::log_io::readPacketLog(o.lcm_log, o.packets_channel, [&](const ogf::log_io::LoggedPacket& p) {
      replayer.sendDatagram(p.host_utime, p.port, p.payload);
    });
    if (!read) {
      spdlog::error("--lcm-log: {}", read.error().message);
      return kExitNothingSent;
    }
    warnRecording(loop, read->problems, read->gaps.summary(o.lcm_log + ": " + o.packets_channel + " batches"));
    if (loop == 0 && read->batches == 0) spdlog::warn("{}: no packet batches on {}", o.lcm_log, o.packets_channel);
  } else {
    auto reader = ds::PcapFileReader::open(o.pcap);
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
        replayer.countSkipped();
        spdlog::debug("record {} skipped: {}", record.index, kindName(record.kind));
        continue;
      }
      replayer.sendDatagram(record.datagram.utime, record.datagram.destination_port, record.datagram.payload);
    }
  }
  replayer.publishRemainingPoses();
  return std::nullopt;
}

// Every loop, until --loop or damage in the capture ends it; `loops_played` counts the loops begun.
Stop playLoops(const Options& o, const Bag& bag, Replayer& replayer, std::string& damage, int& loops_played) {
  int loop = 0;
  for (; loop < o.loops; ++loop) {
    replayer.beginLoop(loop);
    if (auto stop = playOnce(o, bag, loop, replayer, damage)) return stop;
    if (!damage.empty()) break;
  }
  loops_played = loop == o.loops ? o.loops : loop + 1;
  return std::nullopt;
}

// The warnings, the summary line on stdout and the exit code.
int report(const Options& o, const ogf::replay::ReplayCounts& counts, const std::string& damage, int loops_played,
           double seconds) {
  if (!damage.empty()) spdlog::warn("{}: reading stopped at damage: {}; the records before it were sent", o.input(), damage);
  if (counts.skipped > 0) spdlog::warn("{} records skipped (not a whole IPv4/UDP datagram)", counts.skipped);
  if (counts.send_errors > 0) spdlog::warn("{} datagrams could not be sent", counts.send_errors);
  if (counts.pose_errors > 0) spdlog::warn("{} poses could not be published", counts.pose_errors);
  if (!o.fast && counts.late_us_max > 20000)
    spdlog::warn("fell behind the capture clock by up to {:.1f} ms", static_cast<double>(counts.late_us_max) / 1000.0);
  std::fputs(ogf::replay::summaryLine(counts, loops_played, seconds).c_str(), stdout);
  return counts.packets() > 0 ? kExitOk : kExitNothingSent;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (o.pcap.empty() && o.lcm_log.empty() && o.rosbag2.empty()) {
    std::fprintf(stderr, "ogf-replay: give --pcap FILE, --lcm-log FILE or --rosbag2 DIR\n");
    return kExitUsage;
  }
  if (!ogf::transport::setupLoggingAt("ogf-replay", "--log-level", o.log_level)) return kExitUsage;

  Bag bag;
  if (auto stop = openBag(o, bag)) return *stop;
  Destination destination;
  if (auto stop = resolveDestination(o, destination)) return *stop;
  Odometry odometry;
  if (auto stop = loadOdometry(o, odometry)) return *stop;
  if (auto stop = chooseOdometryClock(o, odometry)) return *stop;
  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket(io);
  if (auto stop = openSocket(socket)) return *stop;

  Replayer replayer(o, destination, odometry, socket);
  replayer.start();
  std::string damage;
  int loops_played = 0;
  if (auto stop = playLoops(o, bag, replayer, damage, loops_played)) return *stop;
  return report(o, replayer.counts(), damage, loops_played, replayer.secondsSinceStart());
}
