// Limits on the message set that senders respect and receivers enforce. A message beyond them is
// malformed: receivers reject and count it rather than allocate for it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ogf::messages {

// Largest scan: an HDL-32E in dual-return mode at 300 rpm holds ~280 k points per revolution; 2^20
// leaves room for every supported model and rpm.
inline constexpr std::int32_t kMaxScanPoints = 1 << 20;

// Largest raw batch: one revolution of a dual-return HDL-32E at 300 rpm is ~725 packets.
inline constexpr std::int32_t kMaxPacketsPerBatch = 4096;
inline constexpr std::int32_t kMaxPacketBytes = 1500;

// Most cells in one map_delta_t, chosen so the encoded message (8-byte fingerprint, ~90 bytes of header,
// 19 bytes per cell) plus the channel name stays below LCM_SHORT_MESSAGE_MAX_SIZE (65499 B on Linux):
// one UDP datagram, no LCM fragmentation.
inline constexpr std::int32_t kMaxDeltaCellsPerMessage = 3300;
inline constexpr std::size_t kMaxUnfragmentedMessageBytes = 65499;

// Longest string (requester, command, format, name) a map service request may carry. With it a request's
// largest encoding is known, and a receiver refuses anything longer from its length before decoding it.
inline constexpr std::size_t kMaxRequestTextBytes = 4096;

// The largest encodings of the service requests: an 8-byte fingerprint, the fields in their .lcm order
// (a string is a 4-byte length, its bytes and a NUL), strings of kMaxRequestTextBytes, and for a cell query
// `max_points` points of three floats.
inline constexpr std::size_t kMaxRequestStringBytes = 4 + kMaxRequestTextBytes + 1;
inline constexpr std::size_t maxQueryBytes(std::size_t max_points) {
  return 8 + 8 + 8 + kMaxRequestStringBytes + 1 + 4 + 12 * max_points + 2 * 12;
}
inline constexpr std::size_t kMaxCommandBytes = 8 + 8 + 8 + 4 * kMaxRequestStringBytes + 8 + 32;
inline constexpr std::size_t kMaxMapRequestBytes = 8 + 8 + kMaxRequestStringBytes + 8;

}  // namespace ogf::messages
