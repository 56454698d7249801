// A 64-bit checksum over bytes (FNV-1a over 64-bit words with a final avalanche), used for the map
// checksum the mapper publishes and for the map file's integrity check. Not cryptographic.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include <ogf/core/cell_key.hpp>

namespace ogf::filter {

class MapChecksum {
 public:
  void add(std::span<const std::byte> bytes);
  template <class T>
  void addValue(const T& v) {
    add(std::as_bytes(std::span<const T>(&v, 1)));
  }
  std::uint64_t value() const;
  // Adds bytes[j] to sums[j]: the same states as four add() calls. Spans of one size are taken together
  // (FNV-1a chains one multiply per word, so four side by side keep four chains in flight); others one by
  // one.
  static void addFour(std::array<MapChecksum, 4>& sums, const std::array<std::span<const std::byte>, 4>& bytes);

 private:
  std::uint64_t state_ = 0xCBF29CE484222325ULL;
  std::uint64_t length_ = 0;
};

// The hash of one block for BandedOgf::checksum: its key, its stored values and its cell marks.
std::uint64_t blockChecksum(const CellKey& key, std::span<const float> stored, std::span<const std::uint8_t> marks);

// blockChecksum of four blocks, computed together (MapChecksum::addFour) when their stored values, and
// their marks, have one size, as a map's blocks do.
struct BlockBytes {
  CellKey key;
  std::span<const float> stored;
  std::span<const std::uint8_t> marks;
};
std::array<std::uint64_t, 4> blockChecksums(const std::array<BlockBytes, 4>& blocks);

}  // namespace ogf::filter
