// libFuzzer target: the ROS YAML and VeloView XML calibration parsers on arbitrary text; whatever parses
// must also build a decoder or be refused with a message.
#include <cstdint>
#include <string_view>

#include "ogf/velodyne/calibration.hpp"
#include "ogf/velodyne/packet_decoder.hpp"

namespace ov = ogf::velodyne;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (auto parsed :
       {ov::parseRosYamlCalibration(text, "fuzz.yaml"), ov::parseVeloViewXmlCalibration(text, "fuzz.xml")}) {
    if (!parsed) {
      if (parsed.error().message.empty()) __builtin_trap();
      continue;
    }
    ov::DecoderConfig config;
    config.calibration = *parsed;
    (void)ov::PacketDecoder::create(config);
  }
  return 0;
}
