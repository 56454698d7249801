// ogf.NavGrid (nav_grid_view.hpp).
#include "nav_grid_view.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

namespace py = pybind11;

namespace ogf::python {
namespace {

py::array_t<std::int8_t> gridArray(const std::vector<std::int8_t>& values, std::int32_t width, std::int32_t height) {
  py::array_t<std::int8_t> a({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width)});
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace

NavGridView NavGridView::of(navigation::NavGrid grid) {
  NavGridView v{std::move(grid), {}, {}};
  v.cost = gridArray(v.grid.cost, v.grid.width, v.grid.height);
  v.column_class = gridArray(v.grid.column_class, v.grid.width, v.grid.height);
  return v;
}

void defineNavGrid(py::module_& m) {
  py::class_<NavGridView>(m, "NavGrid",
                          "A 2-D navigation grid projected from a height band of the 3-D map: a dense rectangle over "
                          "the known columns, row 0 the southernmost (lowest y), column 0 the westernmost (lowest x), "
                          "as a ROS OccupancyGrid. A column is occupied when an occupied cell stands in the band, free "
                          "when enough of the band is known free, unknown otherwise; its cost (0..100) is 100 x the "
                          "largest Phi(m + sqrt(s)) of its band's known cells, -1 when unknown.")
      .def_property_readonly("cost", [](const NavGridView& v) { return v.cost; },
                             "numpy int8 array (height, width): cost 0..100 of each column, -1 unknown; "
                             "cost[row, col], row 0 south.")
      .def_property_readonly("column_class", [](const NavGridView& v) { return v.column_class; },
                             "numpy int8 array (height, width): -1 free, 0 unknown, +1 occupied.")
      .def_property_readonly("width", [](const NavGridView& v) { return v.grid.width; }, "Columns along x.")
      .def_property_readonly("height", [](const NavGridView& v) { return v.grid.height; }, "Rows along y.")
      .def_property_readonly("resolution", [](const NavGridView& v) { return v.grid.resolution; },
                             "Metres per column (the 3-D map's cell size).")
      .def_property_readonly("origin_x", [](const NavGridView& v) { return v.grid.originX(); },
                             "Metres (map frame) of the west edge of column 0: the map_server YAML's origin x.")
      .def_property_readonly("origin_y", [](const NavGridView& v) { return v.grid.originY(); },
                             "Metres (map frame) of the south edge of row 0: the map_server YAML's origin y.")
      .def_property_readonly("origin_key",
                             [](const NavGridView& v) { return py::make_tuple(v.grid.origin.x, v.grid.origin.y); },
                             "(x, y) integer key of the south-west column (row 0, column 0).")
      .def_property_readonly("extent",
                             [](const NavGridView& v) {
                               const double r = v.grid.resolution;
                               return py::make_tuple(v.grid.originX(), v.grid.originX() + v.grid.width * r,
                                                     v.grid.originY(), v.grid.originY() + v.grid.height * r);
                             },
                             "(left, right, bottom, top) in metres, for matplotlib's imshow(..., origin='lower', "
                             "extent=grid.extent).")
      .def_property_readonly("floor_z", [](const NavGridView& v) { return v.grid.band.floor_z; },
                             "Metres (map frame) of the floor the band is measured from.")
      .def_property_readonly("min_height", [](const NavGridView& v) { return v.grid.band.min_height; },
                             "Metres above the floor where the band starts.")
      .def_property_readonly("max_height", [](const NavGridView& v) { return v.grid.band.max_height; },
                             "Metres above the floor where the band ends.")
      .def_property_readonly("known_columns", [](const NavGridView& v) { return v.grid.knownColumns(); },
                             "How many columns are free or occupied.")
      .def_property_readonly("checksum", [](const NavGridView& v) { return v.grid.checksum(); },
                             "The grid's checksum (wrapping sum of its known columns' hashes), as the mapper stamps "
                             "on OGF_NAV_GRID.")
      .def(
          "column_at",
          [](const NavGridView& v, double x, double y) {
            const navigation::ColumnKey key{static_cast<std::int32_t>(std::floor(x / v.grid.resolution)),
                                            static_cast<std::int32_t>(std::floor(y / v.grid.resolution))};
            const navigation::NavColumn c = v.grid.at(key);
            return py::make_tuple(static_cast<int>(c.cost), static_cast<int>(c.column_class));
          },
          py::arg("x"), py::arg("y"),
          "(cost, column_class) of the column holding the point (x, y) in metres; (-1, 0) outside the grid.")
      .def("__repr__", [](const NavGridView& v) {
        return "<ogf.NavGrid " + std::to_string(v.grid.width) + "x" + std::to_string(v.grid.height) + " at " +
               std::to_string(v.grid.resolution) + " m, " + std::to_string(v.grid.knownColumns()) + " known columns>";
      });
}

}  // namespace ogf::python
