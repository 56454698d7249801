#include "ogf/rosbag/cdr_reader.hpp"

#include <fmt/format.h>

#include <bit>
#include <string_view>

namespace ogf::rosbag {

Result<CdrReader> CdrReader::open(std::span<const std::uint8_t> message) {
  if (message.size() < kHeaderBytes)
    return Error::inputDamaged(
        fmt::format("CDR message of {} bytes: shorter than its 4-byte encapsulation header", message.size()));
  // The representation identifier (OMG XTypes 7.6.3.1.2): 0x0000 CDR_BE, 0x0001 CDR_LE. Bytes 2-3 are
  // options, which plain CDR leaves unused.
  if (message[0] != 0x00 || message[1] > 0x01)
    return Error::inputDamaged(fmt::format("CDR encapsulation {:02x} {:02x}: not plain CDR (00 00 or 00 01)", message[0],
                             message[1]));
  return CdrReader(message, message[1] == 0x00);
}

void CdrReader::fail(std::size_t at, const char* what, const std::string& why) {
  if (error_.empty()) error_ = fmt::format("byte {} ({}): {}", at, what, why);
}

bool CdrReader::reserve(std::size_t alignment, std::size_t size, const char* what) {
  if (!ok()) return false;
  const std::size_t body = pos_ - kHeaderBytes;
  const std::size_t padding = (alignment - body % alignment) % alignment;
  if (padding > remaining() || size > remaining() - padding) {
    fail(pos_, what, fmt::format("needs {} bytes, {} left", padding + size, remaining()));
    return false;
  }
  pos_ += padding;
  return true;
}

std::uint64_t CdrReader::unsignedOf(std::size_t size) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const std::size_t at = big_endian_ ? pos_ + i : pos_ + size - 1 - i;
    v = (v << 8) | data_[at];
  }
  pos_ += size;
  return v;
}

bool CdrReader::u8(std::uint8_t& v, const char* what) {
  if (!reserve(1, 1, what)) return false;
  v = data_[pos_++];
  return true;
}

bool CdrReader::u32(std::uint32_t& v, const char* what) {
  if (!reserve(4, 4, what)) return false;
  v = static_cast<std::uint32_t>(unsignedOf(4));
  return true;
}

bool CdrReader::i32(std::int32_t& v, const char* what) {
  std::uint32_t u = 0;
  if (!u32(u, what)) return false;
  v = static_cast<std::int32_t>(u);
  return true;
}

bool CdrReader::f64(double& v, const char* what) {
  if (!reserve(8, 8, what)) return false;
  v = std::bit_cast<double>(unsignedOf(8));
  return true;
}

void CdrReader::f64s(std::span<double> out, const char* what) {
  for (double& v : out)
    if (!f64(v, what)) return;
}

bool CdrReader::string(std::string& v, const char* what) {
  std::uint32_t length = 0;
  const std::size_t at = pos_;
  if (!u32(length, what)) return false;
  if (length > remaining()) {
    fail(at, what, fmt::format("string of {} bytes, {} left", length, remaining()));
    return false;
  }
  // Some writers send an empty string as length 0; CDR proper sends length 1 and the NUL.
  if (length == 0) {
    v.clear();
    return true;
  }
  if (data_[pos_ + length - 1] != 0) {
    fail(at, what, fmt::format("string of {} bytes does not end with NUL", length));
    return false;
  }
  const std::string_view chars(reinterpret_cast<const char*>(data_.data() + pos_), length - 1);
  v.assign(chars.substr(0, chars.find('\0')));
  pos_ += length;
  return true;
}

bool CdrReader::sequenceLength(std::uint32_t& n, std::size_t min_element_bytes, const char* what) {
  const std::size_t at = pos_;
  if (!u32(n, what)) return false;
  if (min_element_bytes > 0 && n > remaining() / min_element_bytes) {
    fail(at, what,
         fmt::format("sequence of {} elements of at least {} bytes, {} bytes left", n, min_element_bytes,
                     remaining()));
    return false;
  }
  return true;
}

bool CdrReader::octets(std::size_t n, std::span<const std::uint8_t>& out, const char* what) {
  if (!reserve(1, n, what)) return false;
  out = data_.subspan(pos_, n);
  pos_ += n;
  return true;
}

}  // namespace ogf::rosbag
