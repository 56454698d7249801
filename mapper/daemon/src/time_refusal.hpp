// The verdict of TimeSanity on a scan's or a pose's time, said in the log: a refusal (rate-limited) with the
// times it was judged against, or a clock jump that was followed.
#pragma once

#include <ogf/fusion/time_sanity.hpp>

#include <cstdint>
#include <optional>
#include <string>

#include "ogf/transport/logging.hpp"

namespace ogf::mapper_daemon {

// Whether the message goes on. `what` names it in the log ("scan", "pose", "source front: scan").
bool timePlausible(const std::string& what, fusion::TimeVerdict verdict, const fusion::TimeSanity& clock,
                   std::optional<std::int64_t> expected, std::int64_t utime, std::int64_t wall_utime,
                   transport::LogRateLimiter& log);

}  // namespace ogf::mapper_daemon
