// ogf-mapper's live 2-D navigation grid on LCM (nav.enabled): the NavFeed of the map (nav_feed.hpp) kept
// by the worker after every scan, its updates and keyframes published on channels.nav_grid, keyframe
// requests (map_request_t) heard on channels.nav_request, and the grid's figures in the status.
//
// A request only raises a flag and counts (atomics, on the Asio thread): however many arrive, mapping never
// waits for them and at most one asked-for keyframe a second goes out. A request that does not decode is
// counted in nav_requests_rejected and logged at most once a second, like those on the map request channel.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "ogf/delta/published_cell.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/nav_feed.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/persistence/map_pager.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

class NavPublisher {
 public:
  // Does nothing (publishes nothing, subscribes nothing) unless options.nav.enabled. The band was
  // validated with the options.
  NavPublisher(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared, std::int64_t map_id);
  NavPublisher(const NavPublisher&) = delete;
  NavPublisher& operator=(const NavPublisher&) = delete;

  bool enabled() const { return feed_.has_value(); }

  // Subscribes the request channel on `bus` (the service bus, whose thread runs the handler) and logs the
  // band once; unsubscribe() ends the subscription.
  void subscribe(lcm::LCM& bus);
  void unsubscribe();

  // The worker's (shared.mu not held).
  // The map restored at start: the published cells in memory and those of the regions paged out, read
  // from their pages (a page that cannot be read is left out, and said).
  void restored(std::span<const delta::PublishedCell> cells, const std::vector<std::filesystem::path>& pages);
  // The cells a scan changed, then what is due.
  void scanMapped(std::int64_t scan_utime, std::span<const delta::PublishedCell> changes, std::int64_t now);
  // Between two scans: what is due (an update waiting for its interval, keyframes).
  void turn(std::int64_t now);
  // A map reset: the new map's empty grid, its keyframe at once.
  void newMap(std::int64_t map_id, std::int64_t now);

 private:
  void onRequest();
  void onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why);
  void publish(const std::vector<ogf::nav_grid_t>& messages);
  // The grid's figures and the request counts into the status (takes shared.mu).
  void report();

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;
  std::optional<NavFeed> feed_;
  std::mt19937 drop_rng_;
  // The worker's:
  std::int64_t bytes_sent_ = 0;
  std::int64_t keyframes_sent_ = 0;
  // Written on the Asio thread, read by the worker.
  std::atomic<bool> keyframe_requested_{false};
  std::atomic<std::int64_t> requests_in_{0};
  std::atomic<std::int64_t> requests_rejected_{0};
  transport::LogRateLimiter bad_request_log_;  // the Asio thread's
  std::unique_ptr<transport::Subscriber<ogf::map_request_t>> request_sub_;
};

}  // namespace ogf::mapper_daemon
