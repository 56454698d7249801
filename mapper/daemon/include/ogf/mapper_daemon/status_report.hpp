// ogf-mapper's status on OGF_MAPPER_STATUS, every status_interval_s: the counters the worker and the map
// services keep (SharedState::stats), the intake's counts and states, the services' totals and the mean
// time a scan took to map since the last status. Published from the Asio thread.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/filter/banded_ogf.hpp>
#include <ogf/mapper_status_t.hpp>

#include <boost/asio/steady_timer.hpp>

#include <cstdint>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/mapper_daemon/map_services.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/scan_intake.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "ogf/transport/daemon_loop.hpp"

namespace ogf::mapper_daemon {

// The map's figures in the status: cells, memory and checksum of the whole map, the regions paged out
// (`held`) included. Memory: the filter's map and the published map beside it (the delta stream's state
// of every published cell, a few bytes per cell, so a long run's growth shows). The checksum hashes the
// blocks changed since it was last taken (about 10 ms after a 0.1 m street scan), so the worker computes
// the figures when a status wants them (SharedState::figures_stale), outside the lock the LCM handlers
// share.
struct MapFigures {
  std::int64_t cells = 0;
  std::int64_t memory_bytes = 0;
  std::int64_t filter_checksum = 0;
};
MapFigures mapFiguresOf(const pipeline::ScanMapper& mapper, const delta::DeltaStream& deltas,
                        const filter::BlockHashSum& held);
void fillMapFigures(ogf::mapper_status_t& s, const MapFigures& figures);

class StatusReport {
 public:
  StatusReport(const MapperOptions& options, lcm::LCM& lcm, transport::DaemonLoop& loop, SharedState& shared,
               const ScanIntake& intake, const MapServices& services);
  StatusReport(const StatusReport&) = delete;
  StatusReport& operator=(const StatusReport&) = delete;

  // Publishes every status_interval_s from now on, until stop().
  void start();
  void stop();
  // A scan mapped in `ms`, received at `host_utime_end` (shared.mu held): the status' update times and lag.
  void scanMapped(double ms, std::int64_t host_utime_end);
  // The worker brought the map's figures up to date for a status that waited (SharedState::status_waiting):
  // the status goes out from the Asio thread. Any thread.
  void figuresReady();

 private:
  void arm();
  // Every status_interval_s: the status, or, when the map's figures are stale, a request to the worker for
  // them (figuresReady publishes). A worker that did not answer within a whole interval does not hold the
  // status back: it goes out with the figures of an earlier scan, consistent with that scan's delta_seq.
  void publish();
  // The status message (shared_.mu held), resetting the mean update time.
  ogf::mapper_status_t compose();
  void send(ogf::mapper_status_t& s);

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;
  const ScanIntake& intake_;
  const MapServices& services_;
  boost::asio::steady_timer timer_;
  bool stopped_ = false;  // Asio thread only
  // Under shared_.mu: the update times since the last status.
  double update_ms_sum_ = 0;
  int update_count_ = 0;
};

}  // namespace ogf::mapper_daemon
