// ogf-mapper's live navigation grid on LCM (nav_publisher.hpp).
#include "ogf/mapper_daemon/nav_publisher.hpp"

#include <ogf/messages/limits.hpp>
#include <spdlog/spdlog.h>

#include <cmath>

namespace ogf::mapper_daemon {

namespace {

// A flood of requests costs at most one keyframe a second; a client that asked waits at most that long.
constexpr std::int64_t kRequestedKeyframeGapUs = 1'000'000;

std::int64_t micros(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e6)); }

}  // namespace

NavPublisher::NavPublisher(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared, std::int64_t map_id)
    : options_(options), lcm_(lcm), shared_(shared), drop_rng_(options.test_seed + 1) {
  if (!options.nav.enabled) return;
  const NavFeedTiming timing{micros(options.nav.update_interval_s), micros(options.nav.keyframe_interval_s),
                             kRequestedKeyframeGapUs};
  auto feed = NavFeed::create(options.map.filter.resolution, options.nav.band, map_id, timing);
  if (!feed) {
    // validate() refuses such a band before the daemon is built.
    spdlog::error("nav: {}; the navigation grid is not published", feed.error().message);
    return;
  }
  feed_.emplace(std::move(*feed));
}

void NavPublisher::subscribe(lcm::LCM& bus) {
  if (!feed_) {
    spdlog::info("nav: the navigation grid is off (nav.enabled false)");
    return;
  }
  const auto& band = options_.nav.band;
  const double res = options_.map.filter.resolution;
  const auto layers = band.layers(res);
  spdlog::info("nav: the navigation grid on {}: cells whose centre lies {}..{} m above the floor at z = {} m, layers "
               "{}..{} ({} at {} m; a column is free with {} free layers); changed tiles at most every {} s, the "
               "whole grid every {} s and on request on {}",
               options_.nav_grid_channel, band.min_height, band.max_height, band.floor_z, layers.lo, layers.hi,
               layers.count(), res, band.freeLayersNeeded(res), options_.nav.update_interval_s,
               options_.nav.keyframe_interval_s, options_.nav_request_channel);
  // A request only raises a flag, so LCM need hold few of them.
  constexpr int kRequestQueueCapacity = 16;
  request_sub_ = std::make_unique<transport::Subscriber<ogf::map_request_t>>(
      bus, options_.nav_request_channel,
      [this](const ogf::map_request_t&, const lcm::ReceiveBuffer&, const std::string&) { onRequest(); },
      [this](const std::string& ch, std::size_t size, std::string_view why) { onMalformedRequest(ch, size, why); },
      kRequestQueueCapacity, messages::kMaxMapRequestBytes);
}

void NavPublisher::unsubscribe() { request_sub_.reset(); }

void NavPublisher::onRequest() {
  requests_in_.fetch_add(1, std::memory_order_relaxed);
  keyframe_requested_.store(true, std::memory_order_relaxed);
}

void NavPublisher::onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why) {
  requests_in_.fetch_add(1, std::memory_order_relaxed);
  requests_rejected_.fetch_add(1, std::memory_order_relaxed);
  if (auto n = bad_request_log_.allow()) spdlog::warn("nav request on {} ({} bytes) {} ({} more)", channel, size, why, *n);
}

void NavPublisher::restored(std::span<const delta::PublishedCell> cells,
                            const std::vector<std::filesystem::path>& pages) {
  if (!feed_) return;
  feed_->rebuild(cells);
  for (const auto& page : pages) {
    auto held = persistence::MapPager::publishedCellsOf(page);
    if (!held) {
      spdlog::error("nav: {}: the navigation grid lacks its region until it is mapped again", held.error().message);
      continue;
    }
    feed_->addRestored(*held);
  }
  report();
}

void NavPublisher::scanMapped(std::int64_t scan_utime, std::span<const delta::PublishedCell> changes, std::int64_t now) {
  if (!feed_) return;
  feed_->cellsChanged(changes, scan_utime);
  turn(now);
}

void NavPublisher::turn(std::int64_t now) {
  if (!feed_) return;
  if (keyframe_requested_.exchange(false, std::memory_order_relaxed)) feed_->requestKeyframe();
  const auto out = feed_->turn(now);
  const bool drop = !out.update.empty() && options_.test_drop_nav_fraction > 0 &&
                    std::uniform_real_distribution<double>(0, 1)(drop_rng_) < options_.test_drop_nav_fraction;
  if (!drop) publish(out.update);
  if (!out.keyframe.empty()) {
    publish(out.keyframe);
    ++keyframes_sent_;
    spdlog::debug("nav: keyframe of map {} at seq {}: {} known columns in {} parts", feed_->mapId(), feed_->seq(),
                  feed_->projection().knownColumns(), out.keyframe.size());
  }
  report();
}

void NavPublisher::newMap(std::int64_t map_id, std::int64_t now) {
  if (!feed_) return;
  feed_->newMap(map_id);
  turn(now);
}

void NavPublisher::publish(const std::vector<ogf::nav_grid_t>& messages) {
  for (const auto& m : messages) {
    lcm_.publish(options_.nav_grid_channel, &m);
    bytes_sent_ += m.getEncodedSize();
  }
}

void NavPublisher::report() {
  std::lock_guard lk(shared_.mu);
  auto& s = shared_.stats;
  s.nav_seq = feed_->seq();
  s.nav_known_columns = static_cast<std::int64_t>(feed_->projection().knownColumns());
  s.nav_checksum = static_cast<std::int64_t>(feed_->projection().checksum());
  s.nav_bytes_sent = bytes_sent_;
  s.nav_keyframes_sent = keyframes_sent_;
  s.nav_requests_in = requests_in_.load(std::memory_order_relaxed);
  s.nav_requests_rejected = requests_rejected_.load(std::memory_order_relaxed);
}

}  // namespace ogf::mapper_daemon
