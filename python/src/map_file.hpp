// ogf.load_map and ogf.Map: a map file or snapshot opened as numpy arrays, with the point and box queries
// of filter/map_queries.hpp and the 2-D projection of navigation/nav_projection.hpp.
#pragma once

#include <pybind11/pybind11.h>

namespace ogf::python {

void defineMapFile(pybind11::module_& m);

}  // namespace ogf::python
