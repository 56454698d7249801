// The binary WebSocket frame that carries slots of OccupiedSlots to the page (web/index.html decodes it
// with typed arrays). Little-endian, every array 4-byte aligned:
//
//   offset 0   u32 magic "OGV1" (0x3156474F)
//   4          u32 flags: bit 0 = full (the page empties every slot before applying this frame)
//   8          u32 slot_count: the page needs at least this many boxes
//   12         u32 n: slots in this frame
//   16         f32 resolution, metres
//   20         u32 zero
//   24         u32 slot[n]
//              i32 key[3n]      x, y, z of each slot's cell
//              f32 variance[n]
//              u16 probability[n]  p * 10000, 0xFFFF: the slot is empty
//              zero padding to a multiple of 4 bytes
//
// 22 bytes a cell. A full map goes out in frames of at most kMaxCellsPerFrame slots, the first one full.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/view/occupied_slots.hpp"

namespace ogf::view {

inline constexpr std::uint32_t kCellFrameMagic = 0x3156474F;
inline constexpr std::uint32_t kCellFrameFull = 1;
inline constexpr std::size_t kCellFrameHeaderBytes = 24;
inline constexpr std::size_t kMaxCellsPerFrame = std::size_t{1} << 18;

std::vector<std::uint8_t> encodeCellFrame(const OccupiedSlots& slots, std::span<const std::uint32_t> which,
                                          bool full, double resolution);

// `which` cut into frames of at most `max_cells` slots; only the first is marked full (when `full`). A
// full update of an empty map is one frame with no slots, so the page still clears.
std::vector<std::vector<std::uint8_t>> encodeCellFrames(const OccupiedSlots& slots,
                                                        std::span<const std::uint32_t> which, bool full,
                                                        double resolution,
                                                        std::size_t max_cells = kMaxCellsPerFrame);

struct DecodedCellFrame {
  bool full = false;
  std::uint32_t slot_count = 0;
  float resolution = 0.0f;
  std::vector<std::uint32_t> slot;
  std::vector<SlotCell> cells;
};

// The page's decoding, for tests and tools; nullopt when the bytes are not a well-formed frame.
std::optional<DecodedCellFrame> decodeCellFrame(std::span<const std::uint8_t> bytes);

}  // namespace ogf::view
