// Whether the scans and the odometry are stamped on the same clock. A scan can only be placed with poses
// on its own clock; when the newest pose is far (seconds) from every scan although both keep arriving,
// the two streams live on different clocks (a sensor without GPS on the device clock and odometry on the
// host clock, say) and no scan will ever be mapped. ClockAgreement watches each scan against the newest
// pose, reports the state and when it changes, and says what would fix it. Pure: times come in as
// arguments.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ogf::fusion {

enum class ClockState { kUnknown, kAgree, kDisagree };

// The clocks a scan can be timed on.
enum class ScanClock { kDevice, kHost };

const char* clockName(ScanClock c);

// One scan seen against the odometry: the scan's time on the clock in use and on the other one, and the
// odometry's time to compare with: live, the newest pose received (absent when none arrived recently enough
// to judge); offline, the pose of a whole odometry file nearest to the scan.
struct ClockSample {
  ScanClock clock = ScanClock::kDevice;
  std::int64_t scan_utime = 0;        // on `clock`
  std::int64_t other_scan_utime = 0;  // the same scan on the other clock
  std::optional<std::int64_t> newest_pose_utime;
};

struct ClockVerdict {
  ClockState state = ClockState::kUnknown;
  bool changed = false;               // state differs from the previous sample's
  std::int64_t offset_us = 0;         // scan time minus newest pose time, on the clock in use
  std::int64_t other_offset_us = 0;   // the same with the scan's other clock
};

class ClockAgreement {
 public:
  // Scans and poses further apart than `tolerance_us` are on different clocks.
  explicit ClockAgreement(std::int64_t tolerance_us = 5'000'000) : tolerance_us_(tolerance_us) {}

  ClockVerdict observe(const ClockSample& sample);

  ClockState state() const { return state_; }
  const ClockVerdict& last() const { return last_; }
  const ClockSample& lastSample() const { return sample_; }
  std::int64_t toleranceUs() const { return tolerance_us_; }

  // One line for the log: both clocks' times, the offset, and the fix (the other clock when it agrees,
  // else which clock to stamp the odometry with), named as the key time_base and the program's flag
  // `time_flag` that sets it.
  std::string describe(std::string_view time_flag = "--time-base") const;

 private:
  std::int64_t tolerance_us_;
  ClockState state_ = ClockState::kUnknown;
  ClockVerdict last_{};
  ClockSample sample_{};
};

// A time as UTC, ISO 8601 with milliseconds ("2024-05-01T12:00:00.123Z").
std::string isoUtc(std::int64_t utime);

}  // namespace ogf::fusion
