// Values in the little-endian binary frames of ogf-view (cell_frame.hpp, nav_frame.hpp), written and read
// at any offset.
#pragma once

#include <cstdint>
#include <cstring>

namespace ogf::view::frame_bytes {

template <class T>
void put(std::uint8_t* at, T value) {
  std::memcpy(at, &value, sizeof(T));  // little-endian hosts only (x86-64, arm64)
}

template <class T>
T get(const std::uint8_t* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

}  // namespace ogf::view::frame_bytes
