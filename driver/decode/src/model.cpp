#include "ogf/velodyne/model.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string>

#include "ogf/velodyne/wire_format.hpp"

namespace ogf::velodyne {
namespace {

constexpr std::array<ModelTraits, 5> kTraits{{
    {Model::Unknown, "unknown", 16, 2, 0.002, 110.592, 55.296},
    {Model::Vlp16, "VLP-16", 16, 2, 0.002, 110.592, 55.296},
    {Model::Vlp16HiRes, "VLP-16-HiRes", 16, 2, 0.002, 110.592, 55.296},
    {Model::Vlp32C, "VLP-32C", 32, 1, 0.004, 55.296, 55.296},
    {Model::Hdl32E, "HDL-32E", 32, 1, 0.002, 46.08, 46.08},
}};

std::string normalised(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '-' || c == '_' || c == ' ') continue;
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

}  // namespace

const ModelTraits& traits(Model model) {
  const auto index = static_cast<std::size_t>(model);
  return kTraits[index < kTraits.size() ? index : 0];
}

double channelTimeInBlockUs(Model model, int channel) {
  switch (model) {
    case Model::Hdl32E:
      return 1.152 * channel;
    case Model::Vlp32C:
      return 2.304 * (channel / 2);
    case Model::Vlp16:
    case Model::Vlp16HiRes:
    case Model::Unknown:
      break;
  }
  return 55.296 * (channel / 16) + 2.304 * (channel % 16);
}

int sequenceOfChannel(Model model, int channel) {
  return traits(model).firings_per_block == 2 ? channel / 16 : 0;
}

int laserOfChannel(Model model, int channel) { return traits(model).lasers == 16 ? channel % 16 : channel; }

double packetPeriodUs(Model model, ReturnMode mode) {
  const double blocks = mode == ReturnMode::Dual ? wire::kBlocksPerPacket / 2 : wire::kBlocksPerPacket;
  return blocks * traits(model).block_duration_us;
}

std::optional<std::int64_t> mostPointsPerRevolution(Model model) {
  if (model == Model::Unknown) return std::nullopt;
  constexpr double kSlowestRevolutionUs = 60e6 / 300.0;
  const double packets = kSlowestRevolutionUs / packetPeriodUs(model, ReturnMode::Dual);
  return static_cast<std::int64_t>(std::ceil(packets)) * wire::kBlocksPerPacket * wire::kChannelsPerBlock;
}

std::string_view modelName(Model model) { return traits(model).name; }

std::string_view returnModeName(ReturnMode mode) {
  switch (mode) {
    case ReturnMode::Strongest:
      return "strongest";
    case ReturnMode::Last:
      return "last";
    case ReturnMode::Dual:
      return "dual";
  }
  return "unknown";
}

std::string_view returnTypeName(ReturnType type) {
  switch (type) {
    case ReturnType::Strongest:
      return "strongest";
    case ReturnType::Last:
      return "last";
    case ReturnType::Both:
      return "both";
    case ReturnType::SecondStrongest:
      return "second_strongest";
  }
  return "unknown";
}

std::optional<Model> parseModelName(std::string_view name) {
  const std::string n = normalised(name);
  if (n == "vlp16" || n == "puck" || n == "pucklite" || n == "vlp16lite") return Model::Vlp16;
  if (n == "vlp16hires" || n == "hires" || n == "puckhires" || n == "vlp16hr") return Model::Vlp16HiRes;
  if (n == "vlp32c" || n == "vlp32") return Model::Vlp32C;
  if (n == "hdl32e" || n == "hdl32") return Model::Hdl32E;
  return std::nullopt;
}

std::optional<ReturnMode> parseReturnModeName(std::string_view name) {
  const std::string n = normalised(name);
  if (n == "strongest") return ReturnMode::Strongest;
  if (n == "last") return ReturnMode::Last;
  if (n == "dual") return ReturnMode::Dual;
  return std::nullopt;
}

std::optional<ReturnMode> returnModeFromByte(std::uint8_t byte) {
  switch (byte) {
    case wire::kReturnModeStrongest:
      return ReturnMode::Strongest;
    case wire::kReturnModeLast:
      return ReturnMode::Last;
    case wire::kReturnModeDual:
      return ReturnMode::Dual;
    default:
      return std::nullopt;
  }
}

std::optional<Model> modelFromProductId(std::uint8_t product_id) {
  switch (product_id) {
    case wire::kProductVlp16:
      return Model::Vlp16;
    case wire::kProductPuckHiRes:
      return Model::Vlp16HiRes;
    case wire::kProductVlp32C:
      return Model::Vlp32C;
    case wire::kProductHdl32E:
      return Model::Hdl32E;
    default:
      return std::nullopt;
  }
}

}  // namespace ogf::velodyne
