// ogf.Map (map_file.hpp).
#include "map_file.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <ogf/filter/map_queries.hpp>
#include <ogf/map_formats/map_cells.hpp>
#include <ogf/map_formats/map_loader.hpp>
#include <ogf/navigation/nav_projection.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "cell_arrays.hpp"
#include "errors.hpp"
#include "nav_grid_view.hpp"

namespace py = pybind11;

namespace ogf::python {
namespace {

struct MapFile {
  std::string path;
  std::unique_ptr<map_formats::LoadedMap> loaded;
  map_formats::MapCells cells;
  CellArrays arrays;
};

std::shared_ptr<MapFile> loadMap(const std::filesystem::path& path) {
  auto file = std::make_shared<MapFile>();
  file->path = path.string();
  std::optional<Error> error;
  {
    py::gil_scoped_release unlocked;
    auto loaded = map_formats::loadOgfMap(path);
    if (loaded) {
      file->loaded = std::make_unique<map_formats::LoadedMap>(std::move(*loaded));
      file->cells = map_formats::collectCells(file->loaded->map);
    } else {
      error = loaded.error();
    }
  }
  if (error) raiseLoadError(path, *error);
  const auto& records = file->cells.cells;
  file->arrays = CellArrays::build(records.size(), file->cells.resolution, [&](std::size_t i) {
    return CellRow{records[i].key, records[i].probability, records[i].variance, records[i].cell_class};
  });
  return file;
}

CellKey keyOf(const MapFile& f, const std::array<double, 3>& p) {
  return cellKeyOf(Eigen::Vector3d(p[0], p[1], p[2]), f.cells.resolution);
}

py::dict cellQuery(const MapFile& f, double x, double y, double z) {
  const CellKey key = keyOf(f, {x, y, z});
  const filter::CellQuery q = filter::queryCell(f.loaded->map, key);
  const Eigen::Vector3d c = cellCentre(key, f.cells.resolution);
  py::dict d;
  d["key"] = py::make_tuple(key.x, key.y, key.z);
  d["centre"] = py::make_tuple(c.x(), c.y(), c.z());
  d["allocated"] = q.allocated;
  d["mean"] = q.mean;
  d["variance"] = q.variance;
  d["occupancy_probability"] = q.occupancyProbability;
  d["probability"] = q.predictiveProbability;
  d["cell_class"] = static_cast<int>(q.occupancyClass);
  d["entropy_bits"] = q.entropyBits;
  return d;
}

py::dict boxQuery(const MapFile& f, const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  const CellKey klo = keyOf(f, lo), khi = keyOf(f, hi);
  auto s = filter::summariseBox(f.loaded->map, klo, khi);
  if (!s) raiseValueError(f.path + ": box query: " + s.error().message);
  py::dict d;
  d["lo_key"] = py::make_tuple(klo.x, klo.y, klo.z);
  d["hi_key"] = py::make_tuple(khi.x, khi.y, khi.z);
  d["cells"] = s->cells;
  d["allocated"] = s->allocated;
  d["occupied"] = s->occupied;
  d["free"] = s->free;
  d["unknown"] = s->unknown;
  d["entropy_bits"] = s->entropyBits;
  d["mean_variance"] = s->meanVariance;
  return d;
}

NavGridView project(const MapFile& f, const navigation::NavBand& band) {
  std::optional<navigation::NavGrid> grid;
  std::string error;
  {
    py::gil_scoped_release unlocked;
    auto projection = navigation::NavProjection::create(f.cells.resolution, band);
    if (projection) {
      for (const auto& c : f.cells.cells)
        projection->update(navigation::CellState{c.key, c.probability, c.cell_class, c.variance});
      projection->refresh();
      if (auto dense = projection->grid()) {
        grid = std::move(*dense);
      } else {
        error = f.path + ": " + dense.error().message;
      }
    } else {
      error = f.path + ": projection band: " + projection.error().message;
    }
  }
  if (!grid) raiseValueError(error);
  return NavGridView::of(std::move(*grid));
}

}  // namespace

void defineMapFile(py::module_& m) {
  py::class_<MapFile, std::shared_ptr<MapFile>> cls(
      m, "Map",
      "An ogf map opened from a file (ogf.load_map): every allocated cell as numpy arrays, in the filter's "
      "deterministic order (the rows of `ogf-map --export-csv`), and questions to the full filter state.");
  cls.def_property_readonly("path", [](const MapFile& f) { return f.path; }, "The file the map was read from.")
      .def_property_readonly("resolution", [](const MapFile& f) { return f.cells.resolution; }, "Cell size, metres.")
      .def_property_readonly("kind", [](const MapFile& f) { return f.loaded->kind; },
                             "\"map file\" (ogf-map --out) or \"snapshot\" (ogf-mapper's snapshot.ogfs).")
      .def_property_readonly("seq", [](const MapFile& f) { return f.loaded->seq; },
                             "The snapshot's update sequence; -1 for a map file.")
      .def("__len__", [](const MapFile& f) { return f.cells.cells.size(); }, "The number of allocated cells.")
      .def("__repr__", [](const MapFile& f) {
        return "<ogf.Map " + f.path + ": " + f.loaded->kind + ", " + std::to_string(f.cells.cells.size()) +
               " cells at " + std::to_string(f.cells.resolution) + " m>";
      });
  defineCellArrayProperties(cls, [](MapFile& f) -> const CellArrays& { return f.arrays; });
  cls.def("query", &cellQuery, py::arg("x"), py::arg("y"), py::arg("z"),
          "Everything the filter knows about the cell holding the point (x, y, z) in metres, as a dict: key, "
          "centre, allocated, mean (latent m), variance (s), occupancy_probability (Phi(m), what eq. (3) "
          "thresholds), probability (predictive, Phi(m / sqrt(1 + s))), cell_class (-1 free, 0 unknown, +1 "
          "occupied) and entropy_bits. A cell never allocated answers with the prior (mean 0, unknown).")
      .def("query_box", &boxQuery, py::arg("lo"), py::arg("hi"),
           "A summary of the cells whose keys lie between the cells holding the points lo and hi (x, y, z in "
           "metres, inclusive), as a dict: lo_key, hi_key, cells, allocated, occupied, free, unknown, "
           "entropy_bits (summed) and mean_variance. ValueError when lo > hi on an axis.")
      .def(
          "project",
          [](const MapFile& f, double floor_z, double min_height, double max_height, double min_free_fraction) {
            return project(f, navigation::NavBand{floor_z, min_height, max_height, min_free_fraction});
          },
          py::arg("floor_z") = 0.0, py::arg("min_height") = 0.25, py::arg("max_height") = 1.5,
          py::arg("min_free_fraction") = 0.5,
          "The 2-D navigation grid (ogf.NavGrid) of the height band [floor_z + min_height, floor_z + max_height] "
          "(metres, map frame; cells whose centre lies in it): a column is occupied when an occupied cell stands "
          "in the band, free when no cell does and at least min_free_fraction of the band's layers hold a free "
          "cell, unknown otherwise. The same rule and defaults as the mapper's nav.* keys and "
          "ogf-map --export-nav. ValueError for a band that holds no layer.");

  m.def(
      "load_map", [](const std::filesystem::path& path) { return loadMap(path); }, py::arg("path"),
      "Opens an ogf map file (ogf-map --out) or an ogf-mapper snapshot (snapshot.ogfs, with its pages beside it) "
      "as an ogf.Map. FileNotFoundError when the file does not exist, OSError when it cannot be read, "
      "ogf.MapFileError (a ValueError) naming the file and the reason when it is not a readable map.");
}

}  // namespace ogf::python
