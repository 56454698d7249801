// The model table.
#include "ogf/sim/lidar_model.hpp"

namespace ogf::sim {
namespace {

constexpr std::int64_t kHdl32FiringNs = 1152;   // per laser (driver model.hpp, app. note 63-9277)
constexpr std::int64_t kHdl32BlockNs = 46080;   // 32 firings and the recharge
constexpr std::uint8_t kHdl32ProductId = 0x21;  // docs/wire-format.md §3.6

LidarModel makeVlp16() {
  LidarModel m;
  m.id = LidarModelId::Vlp16;
  m.name = "VLP-16";
  m.product_id = vlp16::kProductId;
  m.lasers = vlp16::kLasers;
  for (std::size_t i = 0; i < vlp16::kLasers; ++i) {
    m.elevation_deg[i] = vlp16::kElevationDeg[i];
    m.vertical_offset_m[i] = vlp16::kVerticalOffsetM[i];
  }
  m.block_ns = vlp16::kBlockNs;
  return m;
}

LidarModel makeHdl32e() {
  LidarModel m;
  m.id = LidarModelId::Hdl32e;
  m.name = "HDL-32E";
  m.product_id = kHdl32ProductId;
  m.lasers = 32;
  // Laser id order, interleaved low/high (driver/decode/src/calibration.cpp kHdl32Vertical); no vertical
  // offsets on this model.
  m.elevation_deg = {-30.67, -9.33, -29.33, -8,     -28,    -6.67, -26.67, -5.33, -25.33, -4,     -24,
                     -2.67,  -22.67, -1.33, -21.33, 0,      -20,   1.33,   -18.67, 2.67,  -17.33, 4,
                     -16,    5.33,  -14.67, 6.67,   -13.33, 8,     -12,    9.33,   -10.67, 10.67};
  m.block_ns = kHdl32BlockNs;
  return m;
}

}  // namespace

std::int64_t LidarModel::channelOffsetNs(int group, int channel) const {
  if (id == LidarModelId::Vlp16) return vlp16::channelOffsetNs(group, channel);
  return group * block_ns + channel * kHdl32FiringNs;
}

const LidarModel& lidarModel(LidarModelId id) {
  static const LidarModel kVlp16 = makeVlp16();
  static const LidarModel kHdl32e = makeHdl32e();
  return id == LidarModelId::Hdl32e ? kHdl32e : kVlp16;
}

std::optional<LidarModelId> parseLidarModel(std::string_view name) {
  if (name == "vlp16") return LidarModelId::Vlp16;
  if (name == "hdl32e") return LidarModelId::Hdl32e;
  return std::nullopt;
}

std::vector<std::string_view> lidarModelNames() { return {"vlp16", "hdl32e"}; }

}  // namespace ogf::sim
