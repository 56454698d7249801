// ogf-mapper's output of the map on LCM: each scan's changes as deltas on OGF_MAP_DELTA, the corrected
// pose on POSE_CORRECTED (with pose correction on), and keyframes of the whole map, periodic
// (keyframe_interval_s) and requested, which KeyframeSender's thread sends while mapping goes on.
// The delta channel keeps to deltas.max_bytes_per_s: before each update the publisher hands the delta
// stream its publishing rule and the bytes the channel's budget holds (the rest of the changes wait in the
// stream); a keyframe spends from the same budget, paced to at most half of its rate, so the deltas keep
// the other half while it goes out.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_delta_t.hpp>

#include <cstdint>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "ogf/correction/scan_pose_correction.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/link_budget.hpp"
#include "ogf/mapper_daemon/keyframe_sender.hpp"
#include "ogf/mapper_daemon/map_persistence.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/transport/logging.hpp"

namespace ogf::mapper_daemon {

class MapPublisher {
 public:
  MapPublisher(const MapperOptions& options, lcm::LCM& lcm, delta::DeltaStream& deltas,
               MapPersistence& persistence, SharedState& shared);
  ~MapPublisher();
  MapPublisher(const MapPublisher&) = delete;
  MapPublisher& operator=(const MapPublisher&) = delete;

  // Starts the keyframe sender's thread; stop() ends it, a keyframe in flight cut short.
  void start();
  void stop();

  // A scan's deltas (the test option test_drop_delta_fraction drops some, for clients' gap recovery); then
  // the rule and allowance of the next update.
  void publishDeltas(const std::vector<ogf::map_delta_t>& deltas);
  // The corrected pose of the scan whose middle is at `utime`.
  void publishCorrectedPose(std::int64_t utime, const correction::ScanCorrection& applied);

  // Keyframes, the worker's. The periodic clock starts with the worker.
  void startClock(std::int64_t now) { last_keyframe_steady_ = now; }
  // Whether a keyframe is to be cut now (`requested`: asked for on the request channel).
  bool keyframeDue(bool requested, std::int64_t now) const;
  // Between two scans: a keyframe asked for while one is going out follows it; a periodic one waits for
  // the sender.
  void keyframeTurn(bool requested, std::int64_t now);
  // The first keyframe of a new map (after a reset): now, or as soon as the sender is free.
  void keyframeOfNewMap();
  // Stops the keyframe in flight, before the pages it reads go away.
  void cancelKeyframe();
  // The pages the keyframe in flight reads (none when none is).
  std::vector<std::string> pinnedPages() const;

 private:
  // Cuts a keyframe and hands it to the sender; false (nothing done) while the sender is busy.
  bool publishKeyframe();
  void keyframeSent(const KeyframeSender::Report& report);
  bool keyframePeriodDue(std::int64_t now) const;
  // Hands the delta stream the rule and the bytes the budget holds now, for its next update: at start,
  // after every update and between scans, and for the stream of a new map.
  void grant();
  // A keyframe part: published and spent from the budget (the sender's thread), and the wait the budget
  // asks before the next one.
  void publishKeyframePart(const ogf::map_delta_t& part);
  std::chrono::microseconds keyframePace();

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  delta::DeltaStream& deltas_;
  MapPersistence& persistence_;
  SharedState& shared_;
  std::mt19937 drop_rng_;
  std::int64_t last_keyframe_steady_ = 0;
  bool keyframe_waiting_ = false;  // requested while the sender was busy
  // The delta channel's bytes (deltas.max_bytes_per_s) and the half a keyframe may take, shared by the
  // worker and the keyframe sender's thread under budget_mu_ (never held while waiting).
  std::mutex budget_mu_;
  delta::LinkBudget channel_budget_;
  delta::LinkBudget keyframe_budget_;
  // The keyframe sender's thread's: one log line per period however many keyframes are asked for.
  transport::LogRateLimiter keyframe_log_{std::chrono::seconds(10)};
  std::unique_ptr<KeyframeSender> keyframe_sender_;
};

}  // namespace ogf::mapper_daemon
