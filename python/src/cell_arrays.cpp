// The numpy arrays of cell_arrays.hpp.
#include "cell_arrays.hpp"

namespace py = pybind11;

namespace ogf::python {

CellArrays CellArrays::build(std::size_t count, double resolution, const std::function<CellRow(std::size_t)>& row) {
  const auto n = static_cast<py::ssize_t>(count);
  CellArrays a{py::array_t<std::int32_t>({n, py::ssize_t{3}}), py::array_t<double>({n, py::ssize_t{3}}),
               py::array_t<double>(n), py::array_t<float>(n), py::array_t<std::int8_t>(n)};
  auto keys = a.keys.mutable_unchecked<2>();
  auto centres = a.centres.mutable_unchecked<2>();
  auto probability = a.probability.mutable_unchecked<1>();
  auto variance = a.variance.mutable_unchecked<1>();
  auto cell_class = a.cell_class.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const CellRow r = row(static_cast<std::size_t>(i));
    const Eigen::Vector3d c = cellCentre(r.key, resolution);
    keys(i, 0) = r.key.x;
    keys(i, 1) = r.key.y;
    keys(i, 2) = r.key.z;
    centres(i, 0) = c.x();
    centres(i, 1) = c.y();
    centres(i, 2) = c.z();
    probability(i) = r.probability;
    variance(i) = r.variance;
    cell_class(i) = r.cell_class;
  }
  // Read-only: the arrays describe the map; writing into them would not change it.
  for (py::array* arr : {static_cast<py::array*>(&a.keys), static_cast<py::array*>(&a.centres),
                         static_cast<py::array*>(&a.probability), static_cast<py::array*>(&a.variance),
                         static_cast<py::array*>(&a.cell_class)})
    arr->attr("setflags")(py::arg("write") = false);
  return a;
}

}  // namespace ogf::python
