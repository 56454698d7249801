// ogf-mapper's intake: the scans of every source (source_intake.hpp) and the odometry of every robot
// (robot_odometry.hpp), received on the Asio thread and held until the worker maps them, and keyframe
// requests on OGF_MAP_REQUEST, received on the service bus's thread. Of the scans that are ready the worker
// takes the oldest among the sources within their share of its time (fusion/fair_share.hpp), so a silent
// or broken source never holds up the others, nor one that floods the worker.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <ogf/fusion/fair_share.hpp>
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/robot_odometry.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/mapper_daemon/source_intake.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

class ScanIntake {
 public:
  using ScanPtr = SourceIntake::ScanPtr;
  // A scan to map and the source it came from.
  struct ReadyScan {
    SourceIntake* source = nullptr;
    std::size_t index = 0;  // the source's place in sources()
    SourceIntake::Pending::Entry entry;
  };

  // The sources resolved and the decoders of raw packet sources (their calibrations loaded).
  struct Sources {
    std::vector<ResolvedSource> resolved;
    std::vector<std::optional<velodyne::PacketStream>> packets;  // one per source
  };
  // Fails naming the source and the field.
  static Result<Sources> prepare(const MapperOptions& options);

  // `io` runs the LCM handlers (the Asio thread).
  ScanIntake(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared, Sources sources,
             boost::asio::io_context& io);
  ScanIntake(const ScanIntake&) = delete;
  ScanIntake& operator=(const ScanIntake&) = delete;

  // Subscribes the scan channels; subscribePoses() the pose channels; subscribeRequests() the keyframe
  // request channel on `bus` (the service bus, whose thread runs onRequest).
  void subscribe();
  void subscribePoses();
  void subscribeRequests(lcm::LCM& bus);
  void unsubscribe();

  // The rest with shared.mu held.
  // The inputs' silence counts from here: from the start of mapping, not from before the map was
  // restored (a long journal replay).
  void restartInputWatch();
  // The next scan to map: of the sources' oldest scans that are ready (their poses have arrived; any, with a
  // static pose), the one that began first among the sources within their share of the worker's time;
  // scans that waited too long expire on the way.
  std::optional<ReadyScan> nextScan(std::int64_t now);
  // The worker spent `us` mapping a scan of the source at `index` (its share, fusion::FairShare).
  void served(std::size_t index, std::int64_t us) { share_.served(index, us); }
  bool keyframeRequested() const { return keyframe_requested_; }
  // Whether a keyframe was requested since the last call.
  bool takeKeyframeRequest();
  // Re-evaluates which inputs of each source arrive and logs a change of state once.
  void watchInputs();
  // The counts of scans, poses and requests, the clocks' and the inputs' state, and each source's own.
  void fillStatus(ogf::mapper_status_t& s) const;
  // Scans received, malformed ones included, and what became of them (sums over the sources).
  std::int64_t scansIn() const;
  fusion::PendingScansCounts pendingCounts() const;
  const std::vector<std::unique_ptr<SourceIntake>>& sources() const { return sources_; }

 private:
  void onRequest(const ogf::map_request_t& request);
  void onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why);
  void fillSums(ogf::mapper_status_t& s) const;
  void fillInputs(ogf::mapper_status_t& s) const;

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;
  std::vector<std::unique_ptr<RobotOdometry>> robots_;
  std::vector<std::unique_ptr<SourceIntake>> sources_;

  // Under shared_.mu:
  fusion::FairShare share_;
  bool keyframe_requested_ = false;
  std::int64_t requests_ = 0;            // well-formed keyframe requests
  std::int64_t malformed_requests_ = 0;  // refused by decodeMessage

  std::vector<fusion::FairShare::Candidate> ready_;  // nextScan's, kept to reuse its memory
  std::unique_ptr<transport::Subscriber<ogf::map_request_t>> request_sub_;
  transport::LogRateLimiter bad_request_log_;
};

}  // namespace ogf::mapper_daemon
