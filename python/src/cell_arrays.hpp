// The cells of a map as numpy arrays, one row per cell in the order they were given: what ogf.Map and
// ogf.MapClient expose as keys, centres, probability, variance and cell_class.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <ogf/core/cell_key.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>

namespace ogf::python {

// One cell as the arrays hold it.
struct CellRow {
  CellKey key;
  double probability = 0.5;  // predictive, [0, 1]
  float variance = 0.0f;
  std::int8_t cell_class = 0;  // -1 free, 0 unknown, +1 occupied
};

struct CellArrays {
  pybind11::array_t<std::int32_t> keys;      // (N, 3) cell keys i, j, k
  pybind11::array_t<double> centres;         // (N, 3) cell centres, metres: (key + 0.5) * resolution
  pybind11::array_t<double> probability;     // (N,)
  pybind11::array_t<float> variance;         // (N,)
  pybind11::array_t<std::int8_t> cell_class; // (N,)

  // Arrays of `count` cells at `resolution`, row i from row(i). Needs the GIL.
  static CellArrays build(std::size_t count, double resolution, const std::function<CellRow(std::size_t)>& row);
};

// Adds the read-only properties keys, centres, probability, variance and cell_class to `cls`, whose
// objects answer them through `arrays(self)`.
template <class Class, class Get>
void defineCellArrayProperties(Class& cls, Get arrays) {
  cls.def_property_readonly(
         "keys", [arrays](typename Class::type& self) { return arrays(self).keys; },
         "numpy int32 array (N, 3): each cell's integer key (i, j, k); the cell covers [i*r, (i+1)*r) on x, and "
         "likewise on y and z, at resolution r.")
      .def_property_readonly(
          "centres", [arrays](typename Class::type& self) { return arrays(self).centres; },
          "numpy float64 array (N, 3): each cell's centre in metres, map frame: (key + 0.5) * resolution.")
      .def_property_readonly(
          "probability", [arrays](typename Class::type& self) { return arrays(self).probability; },
          "numpy float64 array (N,): each cell's predictive occupancy probability Phi(m / sqrt(1 + s)).")
      .def_property_readonly(
          "variance", [arrays](typename Class::type& self) { return arrays(self).variance; },
          "numpy float32 array (N,): each cell's posterior variance s of the latent occupancy.")
      .def_property_readonly(
          "cell_class", [arrays](typename Class::type& self) { return arrays(self).cell_class; },
          "numpy int8 array (N,): each cell's class, -1 free, 0 unknown, +1 occupied (eq. (3) of Sun et al.).");
}

}  // namespace ogf::python
