#include "ogf/velodyne/model_detector.hpp"

#include <cmath>

#include "ogf/velodyne/wire_format.hpp"

namespace ogf::velodyne {

std::optional<Model> ModelDetector::observe(std::uint8_t product_id, std::uint8_t return_mode_byte,
                                            std::uint32_t toh_us) {
  if (model_) return model_;
  ++observed_;
  if (product_id != wire::kProductHdl32E) {
    model_ = modelFromProductId(product_id);
    if (model_) return model_;
    return std::nullopt;  // unknown product: never guessed
  }
  const bool dual = returnModeFromByte(return_mode_byte) == ReturnMode::Dual;
  if (last_toh_ && toh_us > *last_toh_) {
    const double period = toh_us - *last_toh_;
    const ReturnMode mode = dual ? ReturnMode::Dual : ReturnMode::Strongest;
    const double vlp16 = packetPeriodUs(Model::Vlp16, mode);
    const double hdl32 = packetPeriodUs(Model::Hdl32E, mode);
    if (std::abs(period - vlp16) < 0.1 * vlp16)
      model_ = Model::Vlp16;
    else if (std::abs(period - hdl32) < 0.1 * hdl32)
      model_ = Model::Hdl32E;
  }
  last_toh_ = toh_us;
  if (!model_ && observed_ >= kMaxPackets) model_ = Model::Hdl32E;
  return model_;
}

}  // namespace ogf::velodyne
