// The built-in scene presets' YAML text, compiled in from tools/lib/sim/presets/*.yaml by CMake
// (preset_texts.cpp is generated into the build tree), so ogf-sim needs no data files at run time.
#pragma once

#include <span>
#include <string_view>

namespace ogf::sim::detail {

struct PresetText {
  std::string_view name;  // the file name without .yaml
  std::string_view yaml;
};

std::span<const PresetText> presetTexts();

}  // namespace ogf::sim::detail
