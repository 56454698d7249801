// Decides the sensor model of a data stream. Configuration always wins. Otherwise byte 1205 decides,
// except 0x21: the HDL-32E reports it, and so does early (2014) VLP-16 firmware (VeloView's VLP-16 test
// capture, docs/test-data.md §2.1), so the packet period measured from the timestamps decides (VLP-16
// 1327.1 us single / 663.6 us dual, HDL-32E 553.0 / 276.5 us; docs/wire-format.md §3.6 and §4.4).
#pragma once

#include <cstdint>
#include <optional>

#include "ogf/velodyne/model.hpp"

namespace ogf::velodyne {

class ModelDetector {
 public:
  // Undecided 0x21 streams fall back to the product byte after this many packets.
  static constexpr int kMaxPackets = 16;

  explicit ModelDetector(std::optional<Model> configured = std::nullopt) : model_(configured) {}

  // Feeds the next data packet's product byte, return-mode byte and timestamp; returns the model once
  // decided (and forever after).
  std::optional<Model> observe(std::uint8_t product_id, std::uint8_t return_mode_byte, std::uint32_t toh_us);
  std::optional<Model> model() const { return model_; }

 private:
  std::optional<Model> model_;
  std::optional<std::uint32_t> last_toh_;
  int observed_ = 0;
};

}  // namespace ogf::velodyne
