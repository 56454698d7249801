// Return-mode names for the command line and logs.
#include "ogf/sim/vlp16_model.hpp"

namespace ogf::sim::vlp16 {

std::optional<ReturnMode> parseReturnMode(std::string_view name) {
  if (name == "strongest") return ReturnMode::Strongest;
  if (name == "last") return ReturnMode::Last;
  if (name == "dual") return ReturnMode::Dual;
  return std::nullopt;
}

std::string_view toString(ReturnMode mode) {
  switch (mode) {
    case ReturnMode::Strongest: return "strongest";
    case ReturnMode::Last: return "last";
    case ReturnMode::Dual: return "dual";
  }
  return "?";
}

}  // namespace ogf::sim::vlp16
