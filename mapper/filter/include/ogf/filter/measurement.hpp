// One occupancy measurement of a cell (Sec. II): y = +1 occupied, y = -1 free. The project-wide type
// (mapper/core): ray casting produces it, the journal stores it, the filter consumes it.
#pragma once

#include <ogf/core/measurement.hpp>

namespace ogf::filter {

using ogf::Measurement;

}  // namespace ogf::filter
