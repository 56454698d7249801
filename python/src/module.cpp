// The extension module ogf._ogf; python/ogf/__init__.py re-exports it as the package `ogf`.
#include <pybind11/pybind11.h>

#include "errors.hpp"
#include "live_clients.hpp"
#include "map_file.hpp"
#include "nav_grid_view.hpp"

PYBIND11_MODULE(_ogf, m) {
  m.doc() = "ogf's C++ libraries for Python: map files as numpy arrays, queries, the 2-D projection, live clients.";
  ogf::python::registerErrors(m);
  ogf::python::defineNavGrid(m);
  ogf::python::defineMapFile(m);
  ogf::python::defineLiveClients(m);
}
