// A fresh map id: 63 random bits, odd, so no new map shares an id with another or with "none" (0).
#pragma once

#include <cstdint>
#include <random>

namespace ogf::mapper_daemon {

inline std::int64_t newMapId() {
  std::random_device rd;
  const std::uint64_t hi = rd(), lo = rd();
  return static_cast<std::int64_t>(((hi << 32) | lo) & 0x7FFFFFFFFFFFFFFFULL) | 1;
}

}  // namespace ogf::mapper_daemon
