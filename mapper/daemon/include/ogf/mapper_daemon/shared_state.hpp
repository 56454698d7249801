// What ogf-mapper's Asio thread (which receives) and its mapping worker share, under one mutex: the
// wake-up of the worker, the request to stop, its heartbeat, and the counters the worker and the services
// keep for OGF_MAPPER_STATUS. Each part of the daemon takes `mu` around what it touches here.
#pragma once

#include <ogf/mapper_status_t.hpp>

#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace ogf::mapper_daemon {

struct SharedState {
  mutable std::mutex mu;
  std::condition_variable cv;
  bool work = false;  // something arrived for the worker: a scan, a pose, a request
  bool stop = false;
  std::int64_t worker_heartbeat = 0;  // steady time the worker last came round its loop
  ogf::mapper_status_t stats{};       // counters copied into each status message
  // The map changed since the map's figures in `stats` (cells, memory_bytes and filter_checksum, with the
  // delta_seq they belong to) were computed. The checksum takes milliseconds a scan at fine cells, so the
  // worker computes the figures when a status wants them, not after every scan.
  bool figures_stale = false;
  // A status is due and waits for the worker to bring the figures up to date (StatusReport::publish).
  bool status_waiting = false;

  // Wakes the worker (mu held).
  void wake() {
    work = true;
    cv.notify_one();
  }
};

}  // namespace ogf::mapper_daemon
