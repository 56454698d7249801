// The page ogf-view serves (tools/lib/view/web/index.html), compiled into the program so it works the same
// from build/bin and from the package.
#pragma once

#include <string_view>

namespace ogf::view {

std::string_view indexHtml();

}  // namespace ogf::view
