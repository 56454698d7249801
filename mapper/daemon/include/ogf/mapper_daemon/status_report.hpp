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
// blocks the last scan changed (about 10 ms after a 0.1 m street scan), so the worker computes the figures
// before it takes the lock the LCM handlers share.
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

 private:
  void arm();
  void publish();

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;
  const ScanIntake& intake_;
  const MapServices& services_;
  boost::asio::steady_timer timer_;
  // Under shared_.mu: the update times since the last status.
  double update_ms_sum_ = 0;
  int update_count_ = 0;
};

}  // namespace ogf::mapper_daemon
