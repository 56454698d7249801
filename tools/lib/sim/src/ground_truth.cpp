// Ground-truth occupancy: classification over the grid, and the truth.grid writer and reader.
#include "ogf/sim/ground_truth.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "ogf/sim/cell_overlap.hpp"

namespace ogf::sim {
namespace {

std::int32_t floorKey(double v, double r) { return static_cast<std::int32_t>(std::floor(v / r)); }

}  // namespace

std::optional<CellClass> GroundTruth::at(const CellKey& key) const {
  const std::int64_t ix = key.x - min_key.x;
  const std::int64_t iy = key.y - min_key.y;
  const std::int64_t iz = key.z - min_key.z;
  if (ix < 0 || iy < 0 || iz < 0 || ix >= size[0] || iy >= size[1] || iz >= size[2]) return std::nullopt;
  return static_cast<CellClass>(cells[static_cast<std::size_t>(ix + size[0] * (iy + size[1] * iz))]);
}

std::size_t GroundTruth::count(CellClass c) const {
  return static_cast<std::size_t>(std::count(cells.begin(), cells.end(), static_cast<std::uint8_t>(c)));
}

CellKey GroundTruth::keyOf(std::size_t index) const {
  const auto i = static_cast<std::int64_t>(index);
  const std::int64_t nx = size[0];
  const std::int64_t ny = size[1];
  return {static_cast<std::int32_t>(min_key.x + i % nx), static_cast<std::int32_t>(min_key.y + (i / nx) % ny),
          static_cast<std::int32_t>(min_key.z + i / (nx * ny))};
}

namespace {

// Turns open-air cells that no seed reaches (6-connected flood through free cells) into unobservable.
void sealOffUnreachableAir(GroundTruth& truth, const std::vector<Eigen::Vector3d>& seeds) {
  const auto free = static_cast<std::uint8_t>(CellClass::Free);
  const std::int64_t nx = truth.size[0];
  const std::int64_t ny = truth.size[1];
  const std::int64_t nz = truth.size[2];
  std::vector<std::uint8_t> reached(truth.cells.size(), 0);
  std::vector<std::int64_t> stack;
  for (const auto& p : seeds) {
    const CellKey k = cellKeyOf(p, truth.resolution);
    const std::int64_t ix = k.x - truth.min_key.x;
    const std::int64_t iy = k.y - truth.min_key.y;
    const std::int64_t iz = k.z - truth.min_key.z;
    if (ix < 0 || iy < 0 || iz < 0 || ix >= nx || iy >= ny || iz >= nz) continue;
    const std::int64_t i = ix + nx * (iy + ny * iz);
    if (truth.cells[static_cast<std::size_t>(i)] != free || reached[static_cast<std::size_t>(i)]) continue;
    reached[static_cast<std::size_t>(i)] = 1;
    stack.push_back(i);
  }
  while (!stack.empty()) {
    const std::int64_t i = stack.back();
    stack.pop_back();
    const std::int64_t ix = i % nx;
    const std::int64_t iy = (i / nx) % ny;
    const std::int64_t iz = i / (nx * ny);
    const std::array<std::pair<bool, std::int64_t>, 6> neighbours = {{{ix > 0, i - 1},
                                                                       {ix + 1 < nx, i + 1},
                                                                       {iy > 0, i - nx},
                                                                       {iy + 1 < ny, i + nx},
                                                                       {iz > 0, i - nx * ny},
                                                                       {iz + 1 < nz, i + nx * ny}}};
    for (const auto& [inside, j] : neighbours) {
      const auto u = static_cast<std::size_t>(j);
      if (!inside || reached[u] || truth.cells[u] != free) continue;
      reached[u] = 1;
      stack.push_back(j);
    }
  }
  for (std::size_t i = 0; i < truth.cells.size(); ++i) {
    if (truth.cells[i] == free && !reached[i]) truth.cells[i] = static_cast<std::uint8_t>(CellClass::Unobservable);
  }
}

}  // namespace

// Calls visit(index, overlap) for every cell of `grid` the shape meets (only the cells of its key range are
// tried; every cell for an unbounded shape).
template <class Visit>
void forEachCellMeeting(const Shape& shape, const GroundTruth& grid, Visit&& visit) {
  const CellKey lo = grid.min_key;
  const CellKey hi{lo.x + grid.size[0] - 1, lo.y + grid.size[1] - 1, lo.z + grid.size[2] - 1};
  const auto nx = static_cast<std::size_t>(grid.size[0]);
  const auto ny = static_cast<std::size_t>(grid.size[1]);
  const CellClassifier classifier(shape, grid.resolution);
  CellKey from = lo;
  CellKey to = hi;
  if (const auto range = classifier.keyRange()) {
    from = {std::max(lo.x, range->first.x), std::max(lo.y, range->first.y), std::max(lo.z, range->first.z)};
    to = {std::min(hi.x, range->second.x), std::min(hi.y, range->second.y), std::min(hi.z, range->second.z)};
  }
  for (std::int32_t k = from.z; k <= to.z; ++k) {
    for (std::int32_t j = from.y; j <= to.y; ++j) {
      for (std::int32_t i = from.x; i <= to.x; ++i) {
        const CellOverlap o = classifier.classify(CellKey{i, j, k});
        if (o == CellOverlap::None) continue;
        visit(static_cast<std::size_t>(i - lo.x) +
                  nx * (static_cast<std::size_t>(j - lo.y) + ny * static_cast<std::size_t>(k - lo.z)),
              o);
      }
    }
  }
}

GroundTruth computeGroundTruth(const World& world, double resolution,
                               const std::vector<Eigen::Vector3d>& sensor_positions) {
  GroundTruth truth;
  truth.resolution = resolution;
  const double r = resolution;
  const CellKey lo{floorKey(world.bounds.min.x(), r), floorKey(world.bounds.min.y(), r),
                   floorKey(world.bounds.min.z(), r)};
  // The last cell is the one whose half-open box still meets bounds.max.
  const CellKey hi{static_cast<std::int32_t>(std::ceil(world.bounds.max.x() / r)) - 1,
                   static_cast<std::int32_t>(std::ceil(world.bounds.max.y() / r)) - 1,
                   static_cast<std::int32_t>(std::ceil(world.bounds.max.z() / r)) - 1};
  truth.min_key = lo;
  truth.size = {hi.x - lo.x + 1, hi.y - lo.y + 1, hi.z - lo.z + 1};
  const auto nx = static_cast<std::size_t>(truth.size[0]);
  const auto ny = static_cast<std::size_t>(truth.size[1]);
  const auto nz = static_cast<std::size_t>(truth.size[2]);
  truth.cells.assign(nx * ny * nz, static_cast<std::uint8_t>(CellClass::Free));

  for (const Solid& solid : world.solids) {
    forEachCellMeeting(solid.shape, truth, [&](std::size_t idx, CellOverlap o) {
      // Inside any solid beats a surface, a surface beats open air.
      const auto c = static_cast<std::uint8_t>(o == CellOverlap::Inside ? CellClass::Unobservable : CellClass::Occupied);
      truth.cells[idx] = std::max(truth.cells[idx], c);
    });
  }
  if (!sensor_positions.empty()) sealOffUnreachableAir(truth, sensor_positions);
  return truth;
}

std::uint64_t truthChecksum(const std::vector<std::uint8_t>& cells) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (const std::uint8_t b : cells) {
    h ^= b;
    h *= 0x100000001B3ULL;
  }
  return h;
}

Status writeGroundTruth(const std::string& path, const GroundTruth& truth) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{path + ": cannot create"};
  out << "OGF-TRUTH 1\n"
      << fmt::format("resolution {}\n", truth.resolution)
      << fmt::format("min_key {} {} {}\n", truth.min_key.x, truth.min_key.y, truth.min_key.z)
      << fmt::format("size {} {} {}\n", truth.size[0], truth.size[1], truth.size[2])
      << "classes 0=free 1=occupied 2=unobservable\n"
      << "order x-fastest\n"
      << fmt::format("fnv1a64 {:016x}\n", truthChecksum(truth.cells)) << "data\n";
  out.write(reinterpret_cast<const char*>(truth.cells.data()), static_cast<std::streamsize>(truth.cells.size()));
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Ok{};
}

Result<GroundTruth> readGroundTruth(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  auto bad = [&](int line, const std::string& what) { return Error{fmt::format("{}:{}: {}", path, line, what)}; };
  std::string line;
  if (!std::getline(in, line) || line != "OGF-TRUTH 1") return bad(1, "not a ground-truth file (expected 'OGF-TRUTH 1')");
  GroundTruth truth;
  bool have_res = false, have_key = false, have_size = false, have_sum = false;
  std::uint64_t sum = 0;
  int n = 1;
  while (true) {
    if (!std::getline(in, line)) return bad(n + 1, "header ends without a 'data' line");
    ++n;
    if (line == "data") break;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "resolution") {
      have_res = static_cast<bool>(ls >> truth.resolution) && truth.resolution > 0.0;
      if (!have_res) return bad(n, "resolution: expected a positive number");
    } else if (key == "min_key") {
      have_key = static_cast<bool>(ls >> truth.min_key.x >> truth.min_key.y >> truth.min_key.z);
      if (!have_key) return bad(n, "min_key: expected three integers");
    } else if (key == "size") {
      have_size = static_cast<bool>(ls >> truth.size[0] >> truth.size[1] >> truth.size[2]) && truth.size[0] > 0 &&
                  truth.size[1] > 0 && truth.size[2] > 0;
      if (!have_size) return bad(n, "size: expected three positive integers");
    } else if (key == "fnv1a64") {
      have_sum = static_cast<bool>(ls >> std::hex >> sum);
      if (!have_sum) return bad(n, "fnv1a64: expected a hex checksum");
    } else if (key == "order") {
      std::string order;
      ls >> order;
      if (order != "x-fastest") return bad(n, "order: only x-fastest is known");
    } else if (key != "classes") {
      return bad(n, "unknown header field '" + key + "'");
    }
  }
  if (!have_res) return bad(n, "resolution: missing");
  if (!have_key) return bad(n, "min_key: missing");
  if (!have_size) return bad(n, "size: missing");
  if (!have_sum) return bad(n, "fnv1a64: missing");
  const std::size_t total = static_cast<std::size_t>(truth.size[0]) * static_cast<std::size_t>(truth.size[1]) *
                            static_cast<std::size_t>(truth.size[2]);
  truth.cells.resize(total);
  in.read(reinterpret_cast<char*>(truth.cells.data()), static_cast<std::streamsize>(total));
  if (static_cast<std::size_t>(in.gcount()) != total) {
    return Error{fmt::format("{}: data: {} cells expected, {} bytes present", path, total, in.gcount())};
  }
  if (in.peek() != std::char_traits<char>::eof()) return Error{path + ": data: trailing bytes after the cells"};
  if (truthChecksum(truth.cells) != sum) return Error{path + ": data: checksum mismatch (fnv1a64)"};
  for (std::size_t i = 0; i < total; ++i) {
    if (truth.cells[i] > static_cast<std::uint8_t>(CellClass::Unobservable)) {
      return Error{fmt::format("{}: data: byte {} is {}, not a class", path, i, truth.cells[i])};
    }
  }
  return truth;
}

GroundTruth sweptCells(const World& world, const GroundTruth& grid, double duration_s, double step_s) {
  GroundTruth swept = grid;
  swept.cells.assign(grid.cells.size(), static_cast<std::uint8_t>(CellClass::Free));
  for (const MovingSolid& m : world.movers) {
    const double end = std::min(duration_s, m.endS());
    for (double t = m.startS(); t <= end; t += step_s) {
      if (const auto shape = m.placedAt(t)) {
        forEachCellMeeting(*shape, swept, [&](std::size_t idx, CellOverlap) {
          swept.cells[idx] = static_cast<std::uint8_t>(CellClass::Occupied);
        });
      }
    }
  }
  return swept;
}

}  // namespace ogf::sim
