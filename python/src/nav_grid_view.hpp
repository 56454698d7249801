// ogf.NavGrid: a 2-D navigation grid (navigation::NavGrid) as numpy arrays, row 0 the southernmost row.
// Made by ogf.Map.project() and ogf.NavClient.grid().
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <ogf/navigation/nav_grid.hpp>

namespace ogf::python {

struct NavGridView {
  navigation::NavGrid grid;
  pybind11::array_t<std::int8_t> cost;          // (H, W)
  pybind11::array_t<std::int8_t> column_class;  // (H, W)

  // Needs the GIL.
  static NavGridView of(navigation::NavGrid grid);
};

void defineNavGrid(pybind11::module_& m);

}  // namespace ogf::python
