// ogf-mapper's process: subscribes VELODYNE_SCAN and POSE, holds scans until the odometry covers them (or,
// with pose_source static, maps each scan at the configured pose and only counts what arrives on POSE),
// maps them on a worker thread (journal first, then the filter, then OGF_MAP_DELTA), cuts keyframes
// (periodic and requested) that KeyframeSender's thread sends while mapping goes on, snapshots the map,
// and publishes OGF_MAPPER_STATUS. With pose correction on, each scan's pose is corrected (scan matching
// or RBPF) before mapping and the corrected pose goes out on POSE_CORRECTED. The Asio thread only receives
// and queues, so a slow update never stalls LCM; when mapping falls behind, PendingScans drops whole scans
// and counts them. When one input stops arriving (scans without poses, poses without scans) the log says
// which, on which channel, and what to check, once per change, and the status carries the state.
//
// MapperDaemon coordinates the parts and runs the worker's loop: ScanIntake (what arrives), MapPersistence
// (the map on disk), MapPublisher (deltas, corrected poses, keyframes), NavPublisher (the 2-D navigation
// grid), MapServices (queries and commands) and StatusReport (the status message). Queries, commands and
// keyframe requests arrive on a service bus of their own (a second LCM instance, dispatched on its own
// thread), so no volume of them delays the scans and poses.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/deskew.hpp>

#include <Eigen/Geometry>

#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/mapper_daemon/command_auth.hpp"
#include "ogf/mapper_daemon/map_persistence.hpp"
#include "ogf/mapper_daemon/map_publisher.hpp"
#include "ogf/mapper_daemon/map_services.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/nav_publisher.hpp"
#include "ogf/mapper_daemon/scan_intake.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/mapper_daemon/status_report.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/dispatch_thread.hpp"

namespace ogf::mapper_daemon {

class MapperDaemon {
 public:
  // Builds the map (restoring the state directory when one is configured). Scans and poses are received
  // on `lcm` (dispatched by `loop`); queries, commands and keyframe requests on `service_bus`, a second
  // instance on the same bus that the daemon dispatches on a thread of its own, or with them on `lcm` when
  // it is null (a provider, such as memq, whose instances do not share a bus). Everything is published on
  // `lcm`. Fails only on an invalid configuration; persistence problems are logged, reported in the status,
  // and mapping goes on in memory.
  static Result<std::unique_ptr<MapperDaemon>> create(const MapperOptions& options, lcm::LCM& lcm,
                                                       lcm::LCM* service_bus, transport::DaemonLoop& loop);
  ~MapperDaemon();
  MapperDaemon(const MapperDaemon&) = delete;
  MapperDaemon& operator=(const MapperDaemon&) = delete;

  // Starts the worker and the status timer.
  void start();
  // Stops the worker after the scan in hand, writes a final snapshot. Idempotent.
  void stop();

  // True while the worker is alive and not stuck (for the systemd watchdog).
  bool healthy() const;

 private:
  using ScanPtr = ScanIntake::ScanPtr;

  MapperDaemon(const MapperOptions& options, lcm::LCM& lcm, lcm::LCM* service_bus, transport::DaemonLoop& loop,
               pipeline::ScanMapper mapper, std::optional<correction::ScanPoseCorrection> correction,
               std::optional<CommandKey> key, ScanIntake::Sources sources);
  void restore();
  void workerLoop();
  // Maps the scans that are ready (shared_.mu held by `lk`); true when it left with scans still ready,
  // because keyframes, services or a snapshot are due between two scans.
  bool mapReadyScans(std::unique_lock<std::mutex>& lk);
  // Measures a scan the poses cover (placed, unless the pose is static), corrects its pose when
  // correction is on, and maps it (shared_.mu not held).
  void mapPlaced(const fusion::ScanPoints& points, const ScanPtr& scan, SourceIntake& source);
  // Whether something waits that comes between two scans (shared_.mu held).
  bool dueBetweenScans();
  // Keyframes, map services and snapshots, between two scans (shared_.mu not held); true when service
  // work still waits.
  bool betweenScans(bool keyframe_requested);
  // A measured scan's path: journalled, the regions it reaches brought in, folded into the filter, its
  // deltas cut, far regions paged out, the deltas published, the scan counted (the map's figures marked
  // stale: answerStatus computes them when a status is due).
  void mapScan(const ScanPtr& scan, SourceIntake& source);
  void resetMap();
  // The map's figures, and the delta_seq, scans and measurements they belong to (the whole map's and each
  // source's), into the status' counters: a status never pairs one scan's counts with another's checksum.
  // The figures are computed before shared_.mu is taken.
  void refreshMapFigures();
  // The map's figures for a status that waits for them (SharedState::status_waiting), then the status.
  void answerStatus();
  bool staticPose() const { return options_.pose_source == PoseSource::kStatic; }

  MapperOptions options_;
  lcm::LCM& lcm_;
  lcm::LCM* service_bus_;  // null: services on lcm_

  SharedState shared_;
  // Owned by the worker once started.
  pipeline::ScanMapper mapper_;
  std::optional<correction::ScanPoseCorrection> correction_;  // absent in pose_correction mode none
  delta::DeltaStream deltas_;
  pipeline::ChangedCells changes_;

  ScanIntake intake_;
  MapPersistence persistence_;
  MapServices services_;
  StatusReport status_;
  std::thread worker_;
  // After everything its keyframe sender's callbacks use (persistence_, shared_), so it stops first.
  MapPublisher publisher_;
  NavPublisher nav_;
  // Dispatches service_bus_ from start() to stop(); last, so it stops before anything its handlers use.
  std::unique_ptr<transport::DispatchThread> service_dispatch_;
  bool started_ = false;
  bool stopped_ = false;
};

}  // namespace ogf::mapper_daemon
