// Ground truth worlds and samples for ogf-paper2d.
#include "ogf/paper2d/ground_truth.hpp"

#include <algorithm>
#include <charconv>
#include <numeric>

#include "ogf/tools/csv_reader.hpp"
#include "ogf/tools/pgm_reader.hpp"

namespace ogf::paper2d {
namespace {

bool parseInt(const std::string& text, int& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc{} && ptr == end;
}

}  // namespace

GroundTruth builtInGroundTruth() {
  GroundTruth t;
  t.rows = 25;
  t.cols = 25;
  t.occupancy.assign(625, -1);
  auto fill = [&](int r0, int c0, int h, int w) {
    for (int r = r0; r < r0 + h; ++r) {
      for (int c = c0; c < c0 + w; ++c) {
        t.occupancy[static_cast<std::size_t>(r * 25 + c)] = 1;
      }
    }
  };
  fill(3, 3, 6, 8);     // a block
  fill(2, 15, 3, 8);    // a thick wall
  fill(15, 3, 8, 3);    // an L
  fill(20, 3, 3, 8);
  for (int r = 0; r < 25; ++r) {  // a disc of radius 4 around (16, 16)
    for (int c = 0; c < 25; ++c) {
      if ((r - 16) * (r - 16) + (c - 16) * (c - 16) <= 16) {
        fill(r, c, 1, 1);
      }
    }
  }
  return t;
}

bool loadGroundTruth(const std::filesystem::path& path, GroundTruth& out, std::string& error) {
  tools::Greymap map;
  if (!tools::readPgm(path, map, error)) {
    return false;
  }
  if (map.width * map.height > 4096) {
    error = path.string() + ": " + std::to_string(map.width) + "x" + std::to_string(map.height) +
            " cells is too many for the dense OGF and EP (at most 4096)";
    return false;
  }
  out.rows = map.height;
  out.cols = map.width;
  out.occupancy.clear();
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) {
      out.occupancy.push_back(2 * static_cast<int>(map.at(r, c)) < map.maxValue ? 1 : -1);
    }
  }
  return true;
}

std::vector<Sample> drawSamples(const GroundTruth& truth, std::size_t count, std::mt19937& rng) {
  std::vector<int> order(truth.cells());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  order.resize(std::min(count, order.size()));
  std::vector<Sample> samples;
  for (int i : order) {
    samples.push_back({i / truth.cols, i % truth.cols, truth.occupancy[static_cast<std::size_t>(i)]});
  }
  return samples;
}

bool loadSamples(const std::filesystem::path& path, const GroundTruth& truth, std::vector<Sample>& out,
                 std::string& error) {
  std::vector<tools::CsvRow> rows;
  if (!tools::readCsv(path, rows, error)) {
    return false;
  }
  out.clear();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const tools::CsvRow& row = rows[i];
    if (i == 0 && !row.fields.empty() && row.fields[0] == "row") {
      continue;  // header
    }
    int r = 0;
    int c = 0;
    int y = 0;
    const auto where = path.string() + ":" + std::to_string(row.line) + ": ";
    if (row.fields.size() != 3 || !parseInt(row.fields[0], r) || !parseInt(row.fields[1], c) ||
        !parseInt(row.fields[2], y)) {
      error = where + "expected three integers row,col,y";
      return false;
    }
    if (r < 0 || r >= truth.rows || c < 0 || c >= truth.cols) {
      error = where + "cell (" + std::to_string(r) + ", " + std::to_string(c) + ") outside the " +
              std::to_string(truth.rows) + "x" + std::to_string(truth.cols) + " grid";
      return false;
    }
    if (y != 1 && y != -1) {
      error = where + "y must be 1 (occupied) or -1 (free), got " + std::to_string(y);
      return false;
    }
    out.push_back({r, c, static_cast<std::int8_t>(y)});
  }
  if (out.empty()) {
    error = path.string() + ": no samples";
    return false;
  }
  return true;
}

}  // namespace ogf::paper2d
