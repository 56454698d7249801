// ogf-mapper's status (status_report.hpp): the message assembled from the daemon's parts and published.
#include "ogf/mapper_daemon/status_report.hpp"

#include <boost/asio/post.hpp>

#include <chrono>

#include "ogf/mapper_daemon/daemon_time.hpp"

namespace ogf::mapper_daemon {

MapFigures mapFiguresOf(const pipeline::ScanMapper& mapper, const delta::DeltaStream& deltas,
                        const filter::BlockHashSum& held) {
  const auto& map = mapper.filter();
  return {static_cast<std::int64_t>(map.allocatedCells() + held.blocks * map.cellsPerBlock()),
          static_cast<std::int64_t>(map.memoryBytes() + deltas.map().memoryBytes()),
          static_cast<std::int64_t>(map.checksum(held))};
}

void fillMapFigures(ogf::mapper_status_t& s, const MapFigures& figures) {
  s.cells = figures.cells;
  s.memory_bytes = figures.memory_bytes;
  s.filter_checksum = figures.filter_checksum;
}

StatusReport::StatusReport(const MapperOptions& options, lcm::LCM& lcm, transport::DaemonLoop& loop,
                           SharedState& shared, const ScanIntake& intake, const MapServices& services)
    : options_(options), lcm_(lcm), shared_(shared), intake_(intake), services_(services), timer_(loop.io()) {}

void StatusReport::start() { arm(); }

void StatusReport::stop() {
  stopped_ = true;
  boost::system::error_code ec;
  timer_.cancel(ec);
}

void StatusReport::scanMapped(double ms, std::int64_t host_utime_end) {
  shared_.stats.update_ms_last = static_cast<float>(ms);
  update_ms_sum_ += ms;
  ++update_count_;
  shared_.stats.lag_ms = static_cast<float>(static_cast<double>(wallUtime() - host_utime_end) / 1000.0);
}

void StatusReport::arm() {
  timer_.expires_after(std::chrono::microseconds(static_cast<std::int64_t>(options_.status_interval_s * 1e6)));
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    publish();
    arm();
  });
}

void StatusReport::figuresReady() {
  boost::asio::post(timer_.get_executor(), [this] {
    if (stopped_) return;
    ogf::mapper_status_t s;
    {
      std::lock_guard lk(shared_.mu);
      s = compose();
    }
    send(s);
  });
}

void StatusReport::publish() {
  ogf::mapper_status_t s;
  {
    std::lock_guard lk(shared_.mu);
    if (shared_.figures_stale && !shared_.status_waiting) {
      shared_.status_waiting = true;
      shared_.wake();
      return;
    }
    s = compose();
  }
  send(s);
}

ogf::mapper_status_t StatusReport::compose() {
  ogf::mapper_status_t s = shared_.stats;
  intake_.fillStatus(s);
  services_.fillStatus(s);
  s.update_ms_mean = update_count_ > 0 ? static_cast<float>(update_ms_sum_ / update_count_) : 0.0f;
  update_ms_sum_ = 0;
  update_count_ = 0;
  return s;
}

void StatusReport::send(ogf::mapper_status_t& s) {
  s.utime = wallUtime();
  lcm_.publish(options_.status_channel, &s);
}

}  // namespace ogf::mapper_daemon
