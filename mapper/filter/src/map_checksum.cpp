// FNV-1a over 64-bit words, then a splitmix64-style finaliser.
#include "ogf/filter/map_checksum.hpp"

#include <cstring>

namespace ogf::filter {
namespace {
constexpr std::uint64_t kPrime = 0x100000001B3ULL;
}

void MapChecksum::add(std::span<const std::byte> bytes) {
  std::size_t i = 0;
  for (; i + 8 <= bytes.size(); i += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, bytes.data() + i, 8);
    state_ = (state_ ^ word) * kPrime;
  }
  for (; i < bytes.size(); ++i) {
    state_ = (state_ ^ static_cast<std::uint64_t>(bytes[i])) * kPrime;
  }
  length_ += bytes.size();
}

std::uint64_t MapChecksum::value() const {
  std::uint64_t h = state_ ^ length_;
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 31;
  return h;
}

std::uint64_t blockChecksum(const CellKey& key, std::span<const float> stored, std::span<const std::uint8_t> marks) {
  MapChecksum sum;
  sum.addValue(key);
  sum.add(std::as_bytes(stored));
  sum.add(std::as_bytes(marks));
  return sum.value();
}

}  // namespace ogf::filter
