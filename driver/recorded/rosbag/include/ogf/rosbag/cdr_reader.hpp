// A reader of OMG CDR (XCDR1, plain CDR as ROS 2's rmw layers write it) over one serialized message: the
// 4-byte encapsulation header (00 00 big endian, 00 01 little endian), then the body, where every
// primitive is aligned to its own size (8 for float64) counted from the end of the header. Every read is
// checked against the bytes that are left; the first failure is kept, with the byte offset and the field,
// and every later read fails too, so a decoder reads a whole message and checks once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ogf/common/result.hpp>
#include <span>
#include <string>

namespace ogf::rosbag {

class CdrReader {
 public:
  // Errors: fewer than 4 bytes, or an encapsulation other than plain CDR (e.g. XCDR2, parameter lists).
  static Result<CdrReader> open(std::span<const std::uint8_t> message);

  // Each read names the field it reads (`what`) for the error message; false once anything failed.
  bool u8(std::uint8_t& v, const char* what);
  bool i32(std::int32_t& v, const char* what);
  bool u32(std::uint32_t& v, const char* what);
  bool f64(double& v, const char* what);
  void f64s(std::span<double> out, const char* what);  // a fixed array of float64
  // A string: uint32 length counting the terminating NUL, the characters, the NUL.
  bool string(std::string& v, const char* what);
  // A sequence's length, refused when `n` elements of at least `min_element_bytes` each cannot fit in what
  // is left (so a damaged length never makes the caller reserve gigabytes).
  bool sequenceLength(std::uint32_t& n, std::size_t min_element_bytes, const char* what);
  // `n` octets (uint8[n], no alignment), viewed in place.
  bool octets(std::size_t n, std::span<const std::uint8_t>& out, const char* what);

  bool ok() const { return error_.empty(); }
  // "byte 40 (frame_id): ..." with the offset from the start of the message, header included.
  const std::string& error() const { return error_; }
  bool bigEndian() const { return big_endian_; }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }

 private:
  CdrReader(std::span<const std::uint8_t> data, bool big_endian) : data_(data), big_endian_(big_endian) {}
  // Pads to `alignment` (relative to the body) and makes sure `size` bytes follow.
  bool reserve(std::size_t alignment, std::size_t size, const char* what);
  void fail(std::size_t at, const char* what, const std::string& why);
  std::uint64_t unsignedOf(std::size_t size);  // the next `size` bytes in the message's byte order

  std::span<const std::uint8_t> data_;
  bool big_endian_ = false;
  std::size_t pos_ = kHeaderBytes;
  std::string error_;

  static constexpr std::size_t kHeaderBytes = 4;
};

}  // namespace ogf::rosbag
