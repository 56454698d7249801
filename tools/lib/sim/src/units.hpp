#pragma once
// Constants the simulator's sources share (one definition, so a unity build of the library sees one).
#include <limits>
#include <numbers>

namespace ogf::sim {

inline constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

}  // namespace ogf::sim
