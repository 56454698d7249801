#include "ogf/view/cell_frame.hpp"

#include <algorithm>
#include <cstring>

#include "frame_bytes.hpp"

namespace ogf::view {
namespace {

using frame_bytes::get;
using frame_bytes::put;

std::size_t cellFrameBytes(std::size_t n) {
  const std::size_t raw = kCellFrameHeaderBytes + n * (4 + 12 + 4 + 2);
  return (raw + 3) & ~std::size_t{3};
}

}  // namespace

std::vector<std::uint8_t> encodeCellFrame(const OccupiedSlots& slots, std::span<const std::uint32_t> which,
                                          bool full, double resolution) {
  const std::size_t n = which.size();
  std::vector<std::uint8_t> out(cellFrameBytes(n), 0);
  std::uint8_t* p = out.data();
  put<std::uint32_t>(p, kCellFrameMagic);
  put<std::uint32_t>(p + 4, full ? kCellFrameFull : 0u);
  put<std::uint32_t>(p + 8, static_cast<std::uint32_t>(slots.slotCount()));
  put<std::uint32_t>(p + 12, static_cast<std::uint32_t>(n));
  put<float>(p + 16, static_cast<float>(resolution));
  std::uint8_t* slot_at = p + kCellFrameHeaderBytes;
  std::uint8_t* key_at = slot_at + 4 * n;
  std::uint8_t* var_at = key_at + 12 * n;
  std::uint8_t* prob_at = var_at + 4 * n;
  for (std::size_t i = 0; i < n; ++i) {
    const SlotCell& c = slots.slot(which[i]);
    put<std::uint32_t>(slot_at + 4 * i, which[i]);
    put<std::int32_t>(key_at + 12 * i, c.key.x);
    put<std::int32_t>(key_at + 12 * i + 4, c.key.y);
    put<std::int32_t>(key_at + 12 * i + 8, c.key.z);
    put<float>(var_at + 4 * i, c.variance);
    put<std::uint16_t>(prob_at + 2 * i, c.probability);
  }
  return out;
}

std::vector<std::vector<std::uint8_t>> encodeCellFrames(const OccupiedSlots& slots,
                                                        std::span<const std::uint32_t> which, bool full,
                                                        double resolution, std::size_t max_cells) {
  std::vector<std::vector<std::uint8_t>> frames;
  max_cells = std::max<std::size_t>(max_cells, 1);
  for (std::size_t at = 0; at < which.size() || (full && frames.empty()); at += max_cells) {
    const std::size_t n = std::min(max_cells, which.size() - std::min(at, which.size()));
    frames.push_back(encodeCellFrame(slots, which.subspan(std::min(at, which.size()), n), full && at == 0, resolution));
  }
  return frames;
}

std::optional<DecodedCellFrame> decodeCellFrame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kCellFrameHeaderBytes) return std::nullopt;
  const std::uint8_t* p = bytes.data();
  if (get<std::uint32_t>(p) != kCellFrameMagic) return std::nullopt;
  const std::size_t n = get<std::uint32_t>(p + 12);
  if (n > (bytes.size() - kCellFrameHeaderBytes) / 22 || bytes.size() != cellFrameBytes(n)) return std::nullopt;
  DecodedCellFrame f;
  f.full = (get<std::uint32_t>(p + 4) & kCellFrameFull) != 0;
  f.slot_count = get<std::uint32_t>(p + 8);
  f.resolution = get<float>(p + 16);
  const std::uint8_t* slot_at = p + kCellFrameHeaderBytes;
  const std::uint8_t* key_at = slot_at + 4 * n;
  const std::uint8_t* var_at = key_at + 12 * n;
  const std::uint8_t* prob_at = var_at + 4 * n;
  f.slot.resize(n);
  f.cells.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    f.slot[i] = get<std::uint32_t>(slot_at + 4 * i);
    if (f.slot[i] >= f.slot_count) return std::nullopt;
    f.cells[i].key = {get<std::int32_t>(key_at + 12 * i), get<std::int32_t>(key_at + 12 * i + 4),
                      get<std::int32_t>(key_at + 12 * i + 8)};
    f.cells[i].variance = get<float>(var_at + 4 * i);
    f.cells[i].probability = get<std::uint16_t>(prob_at + 2 * i);
  }
  return f;
}

}  // namespace ogf::view
