// ogf-mapper's process: subscribes VELODYNE_SCAN and POSE, holds scans until the odometry covers them (or,
// with pose_source static, maps each scan at the configured pose and only counts what arrives on POSE),
// maps them on a worker thread (journal first, then the filter, then OGF_MAP_DELTA), cuts keyframes
// (periodic and requested) that KeyframeSender's thread sends while mapping goes on, snapshots the map,
// and publishes OGF_MAPPER_STATUS. With pose correction on, each scan's pose
// is corrected (scan matching or RBPF) before mapping and the corrected pose goes out on POSE_CORRECTED. The Asio thread only receives and
// queues, so a slow update never stalls LCM; when mapping falls behind, PendingScans drops whole scans
// and counts them. When one input stops arriving (scans without poses, poses without scans) the log says
// which, on which channel, and what to check, once per change, and the status carries the state.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/input_watch.hpp>
#include <ogf/fusion/pending_scans.hpp>
#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/fusion/time_sanity.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/mapper_daemon/command_auth.hpp"
#include "ogf/mapper_daemon/keyframe_sender.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/persistence/map_pager.hpp"
#include "ogf/persistence/state_directory.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

class MapperDaemon {
 public:
  // Builds the map (restoring the state directory when one is configured) and subscribes. Fails only on
  // an invalid configuration; persistence problems are logged, reported in the status, and mapping goes
  // on in memory.
  static Result<std::unique_ptr<MapperDaemon>> create(const MapperOptions& options, lcm::LCM& lcm,
                                                       transport::DaemonLoop& loop);
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
  using ScanPtr = std::shared_ptr<const ogf::lidar_scan_t>;

  MapperDaemon(const MapperOptions& options, lcm::LCM& lcm, transport::DaemonLoop& loop, pipeline::ScanMapper mapper,
               std::optional<correction::ScanPoseCorrection> correction);
  void restore();
  void onScan(const ogf::lidar_scan_t& scan, const lcm::ReceiveBuffer& rbuf);
  void onPose(const lcm::ReceiveBuffer& rbuf);
  void workerLoop();
  void mapScan(const ScanPtr& scan);
  void publishCorrectedPose(std::int64_t utime, const correction::ScanCorrection& applied);
  // Cuts a keyframe and hands it to the sender; false (nothing done) while the sender is busy.
  bool publishKeyframe();
  void keyframeSent(const KeyframeSender::Report& report);
  // Snapshots (every snapshot_interval_s, on the save command, at stop): the worker encodes the map and
  // begins the snapshot in the state directory; a thread flushes the new pages and writes the file while
  // the worker maps on, journalling each scan into the journals before and after the cut
  // (state_directory.hpp).
  // `wait`: returns with the snapshot in place (the save command, stop). One at a time: a snapshot due while
  // one is written waits for it.
  void takeSnapshot(bool wait = false);
  // Puts the snapshot being written in place once its file is written (`wait`: waits for that); nothing
  // when none is being written.
  void finishSnapshotWrite(bool wait);
  bool snapshotWritten() const;
  // Logs (once per distinct failure) and reports it in the status; `retry`: try the directory again at
  // each snapshot (an I/O failure), not when writing would replace a saved map that could not be used.
  void persistenceFailed(const std::string& what, bool retry);
  bool applyRecovered(const persistence::RecoveredState& rec, const std::string& snapshot_source);
  // Paging (page_out_distance_m): the pager on the state directory's pages/, opened with the directory,
  // and also when paging is off but the saved map has pages (`holds_pages`). Damaged pages lose their
  // regions: logged and reported in the status like other damage.
  void openPager(const std::filesystem::path& pages_dir, bool holds_pages = false);
  void reportPageDamage(const std::vector<persistence::PageDamage>& damage);
  // Pages the far regions out after a scan; a failure is said once and leaves the map in memory.
  void pageOut();
  // Cells, memory and checksum of the whole map, paged-out regions included (mu_ held).
  void fillMapStats();
  void publishStatus();
  // Compares the scan with the newest pose (mu_ held); logs when the clocks start or stop agreeing.
  void watchClocks(const ogf::lidar_scan_t& scan);
  void fillClockStatus(ogf::mapper_status_t& s) const;
  // Re-evaluates which inputs arrive (mu_ held) and logs a change of state once (mapper_inputs.cpp).
  void watchInputs();
  void fillInputStatus(ogf::mapper_status_t& s) const;
  // A message arrived on the pose channel while the pose is static (mu_ held): counted, said once.
  void poseIgnored();
  bool staticPose() const { return options_.pose_source == PoseSource::kStatic; }
  // A missing input is said after 3 s: several scan periods (10 Hz) and far beyond odometry's (50-100 Hz).
  fusion::InputWatchConfig inputWatchConfig() const { return {3.0, !staticPose()}; }
  void armStatusTimer();
  // Map services (map_services.cpp): queries and commands arrive on the Asio thread, which refuses
  // commands that are disabled, unauthenticated or replayed at once; the rest wait in a bounded queue and
  // are served by the worker between scans for at most services.budget_ms_per_scan each time (a box query
  // in chunks over several turns, an export written on its own thread), so they never hold up mapping.
  using ServiceRequest = std::variant<ogf::map_query_t, ogf::map_command_t>;
  enum class CommandRefusal { kUnauthenticated, kReplayed, kBadName, kBusy, kDiskSpace, kOther };
  void subscribeServices();
  void enqueueService(ServiceRequest request);
  // Why the command may not be carried out (mu_ held), nullopt when it may.
  std::optional<std::pair<CommandRefusal, std::string>> authenticate(const ogf::map_command_t& command);
  void refuseCommand(const ogf::map_command_t& command, CommandRefusal why, const std::string& message);
  void refuseQuery(const ogf::map_query_t& query, const std::string& message);
  // Whether service work waits (a request, or a box being answered); the worker's.
  bool servicesWaiting();
  void serve();
  void answer(const ogf::map_query_t& query);
  void stepBox();
  void carryOut(const ogf::map_command_t& command);
  // Export: checked and copied on the worker, written on its own thread; one at a time.
  void startExport(const ogf::map_command_t& command, ogf::map_command_reply_t& reply);
  bool exportWritten() const;
  void finishExport(bool wait);
  void resetMap();
  void refreshMapStats();
  // What the status reports as the map's memory: the filter's map and the published map beside it (the
  // delta stream's state of every published cell, a few bytes per cell, so a long run's growth shows).
  std::int64_t mapMemoryBytes() const;
  static std::int64_t steadyUtime();
  static std::int64_t wallUtime();

  MapperOptions options_;
  lcm::LCM& lcm_;
  transport::DaemonLoop& loop_;

  // With pose_source static: the sensor in the map frame, static_pose after the extrinsic.
  Eigen::Isometry3d static_map_from_sensor_;

  // Owned by the worker once started.
  pipeline::ScanMapper mapper_;
  std::optional<correction::ScanPoseCorrection> correction_;  // absent in pose_correction mode none
  delta::DeltaStream deltas_;
  std::optional<persistence::StateDirectory> state_;
  std::optional<persistence::MapPager> pager_;
  bool paging_failed_ = false;
  std::vector<delta::PublishedCell> changes_;
  std::int64_t last_snapshot_steady_ = 0;
  std::int64_t last_keyframe_steady_ = 0;
  bool keyframe_waiting_ = false;  // requested while the sender was busy
  std::int64_t snapshot_seq_ = 0;
  // What the writer's thread did: flushed the pages written since the last snapshot, then wrote the file.
  struct SnapshotWritten {
    Status status = okStatus();
    double flush_ms = 0;
    double write_ms = 0;
  };
  struct SnapshotWrite {
    std::int64_t seq = 0;
    std::vector<std::string> pages;  // the page files it names
    persistence::MapPager::PageFlush page_flush;
    std::size_t bytes = 0;
    double cut_ms = 0;     // on the worker, in all: encoding, beginning the snapshot
    double encode_ms = 0;  // on the worker: encoding the map in memory
    std::chrono::steady_clock::time_point began;
    std::future<SnapshotWritten> written;
  };
  std::optional<SnapshotWrite> snapshot_write_;
  bool retry_persistence_ = false;
  std::mt19937 drop_rng_;

  // Shared between the Asio thread and the worker.
  mutable std::mutex mu_;
  std::condition_variable cv_;
  fusion::PoseBuffer poses_;
  fusion::PendingScans<ScanPtr> pending_;
  fusion::TimeSanity pose_clock_, scan_clock_;
  bool keyframe_requested_ = false;
  bool work_ = false;
  bool stop_ = false;
  std::int64_t worker_heartbeat_ = 0;
  ogf::mapper_status_t stats_{};  // counters the worker owns, copied into each status message
  std::int64_t malformed_scans_ = 0;
  fusion::ClockAgreement clocks_;
  fusion::InputWatch inputs_;
  bool inputs_were_ok_ = false;     // the inputs have been OK before (a return to OK is said as such)
  std::int64_t poses_ignored_ = 0;  // messages on the pose channel while the pose is static
  std::int64_t last_pose_steady_ = 0;  // when the last pose was accepted (0: never)
  std::int64_t malformed_poses_ = 0;
  std::int64_t requests_ = 0;            // well-formed keyframe requests
  std::int64_t malformed_requests_ = 0;  // refused by decodeMessage
  std::deque<ServiceRequest> service_requests_;
  std::int64_t service_in_ = 0;       // queries and commands received, malformed ones too
  std::int64_t service_refused_ = 0;  // malformed, beyond the limits, or refused for a full queue
  std::optional<CommandKey> command_key_;  // services.key_file, when commands are enabled
  ReplayGuard replay_guard_;
  // The worker's: the box query being answered chunk by chunk, and the export being written.
  struct BoxJob {
    ogf::map_query_t query;
    ChunkedBox chunks;
    std::int64_t map_id;
  };
  std::optional<BoxJob> box_job_;
  struct ExportJob {
    ogf::map_command_reply_t reply;
    std::string command_text;  // for the log: command, name and requester, sanitised
    std::future<Status> written;
  };
  std::optional<ExportJob> export_job_;
  double update_ms_sum_ = 0;
  int update_count_ = 0;

  std::unique_ptr<transport::Subscriber<ogf::lidar_scan_t>> scan_sub_;
  std::unique_ptr<transport::Subscriber<ogf::map_request_t>> request_sub_;
  std::unique_ptr<transport::Subscriber<ogf::map_query_t>> query_sub_;
  std::unique_ptr<transport::Subscriber<ogf::map_command_t>> command_sub_;
  lcm::Subscription* pose_sub_ = nullptr;
  boost::asio::steady_timer status_timer_;
  transport::LogRateLimiter bad_scan_log_, bad_pose_log_, bad_request_log_, jump_log_, bad_time_log_,
      service_log_;
  std::thread worker_;
  // After everything its callbacks use (mu_, stats_, lcm_), so it stops first.
  std::unique_ptr<KeyframeSender> keyframe_sender_;
  bool started_ = false;
  bool stopped_ = false;
};

}  // namespace ogf::mapper_daemon
