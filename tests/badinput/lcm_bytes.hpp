// Test helper: LCM messages as the bytes on the wire, and those bytes with a count field rewritten, to
// make malformed messages (a count claiming more elements than the bytes hold) from valid ones.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace ogf::testing {

// The message encoded as LCM sends it (fingerprint first).
template <class Message>
std::vector<std::uint8_t> encodeMessage(const Message& m) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

// `bytes` with the int32 at `at` replaced by `value`, big-endian as LCM encodes int32.
inline std::vector<std::uint8_t> withInt32At(std::vector<std::uint8_t> bytes, std::size_t at, std::int32_t value) {
  const auto v = static_cast<std::uint32_t>(value);
  for (std::size_t i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
  return bytes;
}

// `bytes` with its last four bytes (the count of a message whose arrays are empty, which LCM encodes
// last) replaced by `count`.
inline std::vector<std::uint8_t> withCount(std::vector<std::uint8_t> bytes, std::int32_t count) {
  const std::size_t at = bytes.size() - 4;
  return withInt32At(std::move(bytes), at, count);
}

}  // namespace ogf::testing
