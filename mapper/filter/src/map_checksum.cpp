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

void MapChecksum::addFour(std::array<MapChecksum, 4>& sums, const std::array<std::span<const std::byte>, 4>& bytes) {
  const std::size_t size = bytes[0].size();
  if (bytes[1].size() != size || bytes[2].size() != size || bytes[3].size() != size) {
    for (std::size_t j = 0; j < 4; ++j) {
      sums[j].add(bytes[j]);
    }
    return;
  }
  std::array<std::uint64_t, 4> state{sums[0].state_, sums[1].state_, sums[2].state_, sums[3].state_};
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    for (std::size_t j = 0; j < 4; ++j) {
      std::uint64_t word = 0;
      std::memcpy(&word, bytes[j].data() + i, 8);
      state[j] = (state[j] ^ word) * kPrime;
    }
  }
  for (std::size_t j = 0; j < 4; ++j) {
    sums[j].state_ = state[j];
    sums[j].length_ += i;
    sums[j].add(bytes[j].subspan(i));  // the bytes after the last whole word, one at a time as add() takes them
  }
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

std::array<std::uint64_t, 4> blockChecksums(const std::array<BlockBytes, 4>& blocks) {
  std::array<MapChecksum, 4> sums;
  std::array<std::span<const std::byte>, 4> stored;
  std::array<std::span<const std::byte>, 4> marks;
  for (std::size_t j = 0; j < 4; ++j) {
    sums[j].addValue(blocks[j].key);
    stored[j] = std::as_bytes(blocks[j].stored);
    marks[j] = std::as_bytes(blocks[j].marks);
  }
  MapChecksum::addFour(sums, stored);
  MapChecksum::addFour(sums, marks);
  return {sums[0].value(), sums[1].value(), sums[2].value(), sums[3].value()};
}

}  // namespace ogf::filter
