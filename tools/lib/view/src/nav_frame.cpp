#include "ogf/view/nav_frame.hpp"

#include <algorithm>
#include <cstring>

#include "frame_bytes.hpp"

namespace ogf::view {
namespace {

using frame_bytes::get;
using frame_bytes::put;

std::size_t navFrameBytes(std::size_t n) { return kNavFrameHeaderBytes + n * (8 + 2 * kNavTileColumns); }

std::vector<std::uint8_t> encodeNavFrame(std::span<const NavTile> tiles, bool full, double resolution,
                                         double floor_z) {
  const std::size_t n = tiles.size();
  std::vector<std::uint8_t> out(navFrameBytes(n), 0);
  std::uint8_t* p = out.data();
  put<std::uint32_t>(p, kNavFrameMagic);
  put<std::uint32_t>(p + 4, full ? kNavFrameFull : 0u);
  put<std::uint32_t>(p + 8, static_cast<std::uint32_t>(n));
  put<std::uint32_t>(p + 12, static_cast<std::uint32_t>(navigation::kTileSize));
  put<float>(p + 16, static_cast<float>(resolution));
  put<float>(p + 20, static_cast<float>(floor_z));
  std::uint8_t* key_at = p + kNavFrameHeaderBytes;
  std::uint8_t* cost_at = key_at + 8 * n;
  std::uint8_t* class_at = cost_at + kNavTileColumns * n;
  for (std::size_t i = 0; i < n; ++i) {
    put<std::int32_t>(key_at + 8 * i, tiles[i].key.x);
    put<std::int32_t>(key_at + 8 * i + 4, tiles[i].key.y);
    std::memcpy(cost_at + kNavTileColumns * i, tiles[i].cost.data(), kNavTileColumns);
    std::memcpy(class_at + kNavTileColumns * i, tiles[i].column_class.data(), kNavTileColumns);
  }
  return out;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> encodeNavFrames(std::span<const NavTile> tiles, bool full, double resolution,
                                                       double floor_z, std::size_t max_tiles) {
  std::vector<std::vector<std::uint8_t>> frames;
  max_tiles = std::max<std::size_t>(max_tiles, 1);
  for (std::size_t at = 0; at < tiles.size() || (full && frames.empty()); at += max_tiles) {
    const std::size_t from = std::min(at, tiles.size());
    const std::size_t n = std::min(max_tiles, tiles.size() - from);
    frames.push_back(encodeNavFrame(tiles.subspan(from, n), full && at == 0, resolution, floor_z));
  }
  return frames;
}

std::optional<DecodedNavFrame> decodeNavFrame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kNavFrameHeaderBytes) return std::nullopt;
  const std::uint8_t* p = bytes.data();
  if (get<std::uint32_t>(p) != kNavFrameMagic) return std::nullopt;
  if (get<std::uint32_t>(p + 12) != static_cast<std::uint32_t>(navigation::kTileSize)) return std::nullopt;
  const std::size_t n = get<std::uint32_t>(p + 8);
  if (n > bytes.size() / (8 + 2 * kNavTileColumns) || bytes.size() != navFrameBytes(n)) return std::nullopt;
  DecodedNavFrame f;
  f.full = (get<std::uint32_t>(p + 4) & kNavFrameFull) != 0;
  f.resolution = get<float>(p + 16);
  f.floor_z = get<float>(p + 20);
  const std::uint8_t* key_at = p + kNavFrameHeaderBytes;
  const std::uint8_t* cost_at = key_at + 8 * n;
  const std::uint8_t* class_at = cost_at + kNavTileColumns * n;
  f.tiles.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto& t = f.tiles[i];
    t.key = {get<std::int32_t>(key_at + 8 * i), get<std::int32_t>(key_at + 8 * i + 4)};
    const auto* c = reinterpret_cast<const std::int8_t*>(cost_at + kNavTileColumns * i);
    const auto* k = reinterpret_cast<const std::int8_t*>(class_at + kNavTileColumns * i);
    t.cost.assign(c, c + kNavTileColumns);
    t.column_class.assign(k, k + kNavTileColumns);
  }
  return f;
}

}  // namespace ogf::view
