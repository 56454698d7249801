// A check of a received buffer's array counts before LCM decodes it. lcm-gen's decode() resizes each
// vector to the count it reads *before* checking that the bytes are there, so a 40-byte message claiming
// 2^31 points would allocate gigabytes, and a negative count throws from inside the LCM callback. This
// reads only the counts (walking the fixed fields in the .lcm files' order) and refuses a buffer that
// cannot hold what it claims. Every type with variable arrays has a check; others need none.
#pragma once

#include <bot_core/pose_t.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/nav_grid_t.hpp>
#include <ogf/odometry_t.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "ogf/messages/limits.hpp"

namespace ogf::messages {

// Reads big-endian fields from a received buffer without running past its end.
class CountReader {
 public:
  CountReader(const void* data, std::size_t size) : p_(static_cast<const std::uint8_t*>(data)), size_(size) {}
  bool skip(std::size_t n) {
    if (n > size_ - pos_) return ok_ = false;
    pos_ += n;
    return true;
  }
  std::optional<std::int32_t> int32() {
    if (size_ - pos_ < 4) {
      ok_ = false;
      return std::nullopt;
    }
    const std::uint32_t v = (std::uint32_t{p_[pos_]} << 24) | (std::uint32_t{p_[pos_ + 1]} << 16) |
                            (std::uint32_t{p_[pos_ + 2]} << 8) | std::uint32_t{p_[pos_ + 3]};
    pos_ += 4;
    return static_cast<std::int32_t>(v);
  }
  // A string: int32 length (with the NUL, so at least 1), then the bytes.
  bool string() {
    const auto n = int32();
    return n && *n >= 1 && skip(static_cast<std::size_t>(*n));
  }
  std::size_t remaining() const { return size_ - pos_; }
  bool ok() const { return ok_; }

 private:
  const std::uint8_t* p_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

// nullopt when `count` elements of `bytes_each` fit in what remains and count is within [0, limit].
inline std::optional<std::string> checkCount(CountReader& r, std::optional<std::int32_t> count, std::size_t bytes_each,
                                             std::int64_t limit, const char* field) {
  if (!count) return std::string(field) + ": buffer ends before the count";
  if (*count < 0) return std::string(field) + ": negative count " + std::to_string(*count);
  if (*count > limit) return std::string(field) + ": count " + std::to_string(*count) + " above the limit " + std::to_string(limit);
  const auto need = static_cast<std::uint64_t>(*count) * bytes_each;
  if (need > r.remaining())
    return std::string(field) + ": claims " + std::to_string(*count) + " elements (" + std::to_string(need) +
           " bytes) but " + std::to_string(r.remaining()) + " bytes remain";
  return std::nullopt;
}

template <class Message>
struct EncodedSizeCheck {
  static std::optional<std::string> check(const void*, std::size_t) { return std::nullopt; }
};

template <>
struct EncodedSizeCheck<ogf::lidar_scan_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    // fingerprint, utime, seq, frame_id, then 55 bytes of fixed fields up to num_points.
    if (!(r.skip(8 + 8 + 8) && r.string() && r.skip(8 + 8 + 1 + 8 + 8 + 1 + 1 + 4 + 4 + 4 + 4 + 4)))
      return "header truncated";
    // Per point: x, y, z, azimuth_deg, time_offset_ns (4 bytes each), intensity, ring, laser_id, return_type.
    return checkCount(r, r.int32(), 5 * 4 + 4, kMaxScanPoints, "num_points");
  }
};

template <>
struct EncodedSizeCheck<ogf::map_delta_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!r.skip(8 + 8 + 8 + 8 + 8 + 1 + 4 + 4 + 8 + 8)) return "header truncated";
    // Per cell: key x, y, z (4 each), probability (2), class (1), variance (4).
    return checkCount(r, r.int32(), 12 + 2 + 1 + 4, kMaxDeltaCellsPerMessage, "num_cells");
  }
};

template <>
struct EncodedSizeCheck<ogf::nav_grid_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    // fingerprint, utime, map_id, seq, base_seq, kind, part_index, part_count, resolution, floor_z,
    // min_height, max_height, grid_checksum, tile_size.
    if (!r.skip(8 + 8 + 8 + 8 + 8 + 1 + 4 + 4 + 8 + 8 + 8 + 8 + 8 + 4)) return "header truncated";
    // tile_x and tile_y (4 bytes each per tile), then per column cost and class (1 byte each): each count
    // is bounded by the bytes that follow it (the receiver checks the tile size and part limits).
    const auto tiles = r.int32();
    if (auto bad = checkCount(r, tiles, 2 * 4, std::int64_t{1} << 24, "num_tiles")) return bad;
    r.skip(static_cast<std::size_t>(*tiles) * 2 * 4);
    return checkCount(r, r.int32(), 2, std::int64_t{1} << 30, "num_columns");
  }
};

template <>
struct EncodedSizeCheck<ogf::velodyne_packets_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8) && r.string())) return "header truncated";
    const auto n = r.int32();
    // Per packet: host_utime (8), port (4), length (4).
    if (auto e = checkCount(r, n, 16, kMaxPacketsPerBatch, "num_packets")) return e;
    r.skip(static_cast<std::size_t>(*n) * 16);
    return checkCount(r, r.int32(), 1, static_cast<std::int64_t>(kMaxPacketsPerBatch) * kMaxPacketBytes, "num_bytes");
  }
};

// Types whose only variable fields are strings: lcm-gen's decode trusts a string's length too, and a length
// of -2^31 wraps to 2^31 - 1 (assign() then reads 2 GiB past the buffer; a 37-byte map_request_t did that
// to ogf-mapper, found by tests/fuzz/messages). Each string's length must be within what remains.
template <>
struct EncodedSizeCheck<ogf::map_request_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8) && r.string())) return "requester: length beyond the buffer";
    return std::nullopt;
  }
};

template <>
struct EncodedSizeCheck<ogf::driver_status_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8) && r.string())) return "source: length beyond the buffer";
    // model, return_mode, three rates, nine counters, pps_state, gps_fix_valid, then nmea.
    if (!(r.skip(1 + 1 + 3 * 4 + 9 * 8 + 1 + 1) && r.string())) return "nmea: length beyond the buffer";
    return std::nullopt;
  }
};

template <>
struct EncodedSizeCheck<ogf::mapper_status_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    // utime and nine counters, three timings, five more int64, persistence_ok, then persistence_error.
    if (!(r.skip(8 + 10 * 8 + 3 * 4 + 5 * 8 + 1) && r.string())) return "persistence_error: length beyond the buffer";
    // Nine int64 (requests to service requests), clocks and scan_clock, clock_offset_us, the seven service
    // counters, then last_requester.
    if (!(r.skip(9 * 8 + 2 + 8 + 7 * 8) && r.string())) return "last_requester: length beyond the buffer";
    return std::nullopt;
  }
};

// The map services' requests, which any host on the bus can send (OGF_MAP_QUERY, OGF_MAP_COMMAND).
template <>
struct EncodedSizeCheck<ogf::map_query_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8 + 8) && r.string())) return "requester: length beyond the buffer";
    if (!r.skip(1)) return "kind: beyond the buffer";
    // Points of x, y, z floats; the daemon answers at most 10 000 (map_query_answer.hpp), this only bounds
    // what decode() may allocate.
    return checkCount(r, r.int32(), 3 * 4, 1 << 20, "num_points");
  }
};

template <>
struct EncodedSizeCheck<ogf::map_command_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8 + 8) && r.string())) return "requester: length beyond the buffer";
    if (!r.string()) return "command: length beyond the buffer";
    if (!r.string()) return "format: length beyond the buffer";
    if (!r.string()) return "path: length beyond the buffer";
    return std::nullopt;
  }
};

template <>
struct EncodedSizeCheck<ogf::odometry_t> {
  static std::optional<std::string> check(const void* data, std::size_t size) {
    CountReader r(data, size);
    if (!(r.skip(8 + 8) && r.string() && r.string() && r.skip(3 * 8 + 4 * 8))) return "header truncated";
    return checkCount(r, r.int32(), 8, 36, "num_covariance");
  }
};

}  // namespace ogf::messages
