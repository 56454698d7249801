// Whether a scan the odometry left out lies on another clock than the odometry: the scan's start on the
// clock in use and on the other one against the odometry's nearest pose, judged by the daemon's
// fusion::ClockAgreement (its describe() gives both times, the offset and the time_base that fixes it).
#pragma once

#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/pose_buffer.hpp>

#include <optional>

#include "ogf/map_io/scan_record.hpp"

namespace ogf::map_io {

// The judgement when the scan is farther from every pose than ClockAgreement's tolerance, else nullopt
// (and nullopt without poses).
std::optional<fusion::ClockAgreement> clockMismatch(const ScanRecord& scan, TimeBase base,
                                                    const fusion::PoseBuffer& poses);

}  // namespace ogf::map_io
