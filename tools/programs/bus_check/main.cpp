// ogf-bus-check: joins the LCM bus, publishes one message of every type in the ogf message set on its
// channel, receives each back through the same Asio bridge the daemons use, and prints a table of
// channels, types, fingerprints and sizes. Exit 0 when every message made the round trip.
#include <CLI/CLI.hpp>
#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>

#include <bot_core/pose_t.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_query_reply_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/nav_grid_t.hpp>
#include <ogf/odometry_t.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace {

struct Row {
  std::string channel;
  std::string type;
  std::uint64_t fingerprint = 0;
  int bytes = 0;
  bool received = false;
  std::function<void()> publish;  // sends the probe message again
};

template <class Message>
struct Probe {
  Row row;
  std::unique_ptr<ogf::transport::Subscriber<Message>> sub;
};

template <class Message>
void addProbe(lcm::LCM& lcm, std::vector<Row*>& rows, std::vector<std::shared_ptr<void>>& keep,
              const std::string& channel, Message msg) {
  auto probe = std::make_shared<Probe<Message>>();
  probe->row = {channel, Message::getTypeName(), static_cast<std::uint64_t>(Message::getHash()),
                msg.getEncodedSize(), false, {}};
  Row* row = &probe->row;
  probe->sub = std::make_unique<ogf::transport::Subscriber<Message>>(
      lcm, channel, [row](const Message&, const lcm::ReceiveBuffer&, const std::string&) { row->received = true; },
      [](const std::string& ch, std::size_t size, std::string_view why) {
        spdlog::error("message on {} ({} bytes) {}", ch, size, why);
      });
  row->publish = [&lcm, channel, msg] { lcm.publish(channel, &msg); };
  rows.push_back(row);
  keep.push_back(probe);
  row->publish();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Publish one message of every ogf LCM type and receive it back; prints the message set."};
  std::string url;
  double timeout_s = 3.0;
  std::string prefix = "OGF_BUS_CHECK_";
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--timeout", timeout_s, "Seconds to wait for the round trip")->check(ogf::cli::positive());
  app.add_option("--channel-prefix", prefix, "Prefix of the channels used, so live channels are untouched");
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  ogf::transport::setupLogging("ogf-bus-check");
  const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(url));
  lcm::LCM lcm(resolved);
  if (!lcm.good()) {
    spdlog::error("cannot join the LCM bus {} (udpm needs a multicast route: scripts/multicast-loopback.sh)",
                  resolved);
    return 2;
  }
  if (const auto why = ogf::transport::receiveProblem(lcm, resolved)) {
    spdlog::error("{}", *why);
    return 2;
  }

  ogf::transport::DaemonLoop loop;
  ogf::transport::LcmAsioBridge bridge(loop.io(), lcm);
  std::vector<Row*> rows;
  std::vector<std::shared_ptr<void>> keep;

  ogf::velodyne_packets_t packets{};
  packets.num_packets = 1;
  packets.host_utime = {0};
  packets.port = {2368};
  packets.length = {1206};
  packets.num_bytes = 1206;
  packets.data.assign(1206, 0);
  ogf::lidar_scan_t scan{};
  scan.frame_id = "velodyne";
  ogf::odometry_t odom{};
  odom.frame_id = "odom";
  odom.child_frame_id = "base_link";
  odom.orientation[0] = 1.0;
  bot_core::pose_t pose{};
  pose.orientation[0] = 1.0;
  ogf::map_delta_t delta{};
  ogf::map_request_t request{};
  request.requester = "ogf-bus-check";
  request.last_seq = -1;
  ogf::driver_status_t driver_status{};
  ogf::mapper_status_t mapper_status{};
  ogf::map_query_t query{};
  query.requester = "ogf-bus-check";
  ogf::map_query_reply_t query_reply{};
  ogf::map_command_t command{};
  command.requester = "ogf-bus-check";
  ogf::map_command_reply_t command_reply{};
  ogf::nav_grid_t nav{};
  ogf::map_request_t nav_request = request;

  addProbe(lcm, rows, keep, prefix + "VELODYNE_PACKETS", packets);
  addProbe(lcm, rows, keep, prefix + "VELODYNE_SCAN", scan);
  addProbe(lcm, rows, keep, prefix + "POSE", odom);
  addProbe(lcm, rows, keep, prefix + "POSE_BOT_CORE", pose);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_DELTA", delta);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_REQUEST", request);
  addProbe(lcm, rows, keep, prefix + "VELODYNE_STATUS", driver_status);
  addProbe(lcm, rows, keep, prefix + "OGF_MAPPER_STATUS", mapper_status);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_QUERY", query);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_QUERY_REPLY", query_reply);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_COMMAND", command);
  addProbe(lcm, rows, keep, prefix + "OGF_MAP_COMMAND_REPLY", command_reply);
  addProbe(lcm, rows, keep, prefix + "OGF_NAV_GRID", nav);
  addProbe(lcm, rows, keep, prefix + "OGF_NAV_REQUEST", nav_request);

  // udpm joins the multicast group lazily, so a first publish can race the receive socket: messages not
  // yet back are sent again every 200 ms until the timeout.
  boost::asio::steady_timer timer(loop.io());
  timer.expires_after(std::chrono::milliseconds(static_cast<int>(timeout_s * 1000)));
  timer.async_wait([&](const boost::system::error_code&) { loop.requestStop(0); });
  boost::asio::steady_timer poll(loop.io());
  int polls = 0;
  std::function<void()> check = [&] {
    bool all = true;
    for (const Row* r : rows) all = all && r->received;
    if (all) {
      loop.requestStop(0);
      return;
    }
    if (++polls % 10 == 0) {
      for (const Row* r : rows)
        if (!r->received) r->publish();
    }
    poll.expires_after(std::chrono::milliseconds(20));
    poll.async_wait([&](const boost::system::error_code& ec) { if (!ec) check(); });
  };
  check();
  loop.run();

  std::printf("LCM bus: %s\n\n%-40s %-22s %-18s %7s  %s\n", resolved.c_str(), "channel", "type",
              "fingerprint", "bytes", "round trip");
  int missing = 0;
  for (const Row* r : rows) {
    std::printf("%-40s %-22s 0x%016llx %7d  %s\n", r->channel.c_str(), r->type.c_str(),
                static_cast<unsigned long long>(r->fingerprint), r->bytes, r->received ? "ok" : "MISSING");
    if (!r->received) ++missing;
  }
  std::printf("\n%zu channels, %d received, %d missing\n", rows.size(), static_cast<int>(rows.size()) - missing,
              missing);
  return missing == 0 ? 0 : 1;
}
