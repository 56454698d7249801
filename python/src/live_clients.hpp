// ogf.MapClient and ogf.NavClient: the mapper's OGF_MAP_DELTA and OGF_NAV_GRID streams followed live over
// LCM (stream_follower.hpp), the map as the same arrays as ogf.Map and the grid as an ogf.NavGrid.
#pragma once

#include <pybind11/pybind11.h>

namespace ogf::python {

void defineLiveClients(pybind11::module_& m);

}  // namespace ogf::python
