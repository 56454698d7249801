// The 2-D world of the paper's Sec. VI-A: a grid of cells, each occupied (+1) or free (-1), and the
// noise-free samples taken from it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace ogf::paper2d {

struct GroundTruth {
  int rows = 0;
  int cols = 0;
  std::vector<std::int8_t> occupancy;  // row-major, +1 occupied, -1 free

  std::int8_t at(int row, int col) const {
    return occupancy[static_cast<std::size_t>(row * cols + col)];
  }
  std::size_t cells() const { return occupancy.size(); }
};

struct Sample {
  int row = 0;
  int col = 0;
  std::int8_t y = 1;  // +1 occupied, -1 free
};

// The built-in 25 × 25 world: a block, a thick wall, an L and a disc (about a quarter of it occupied).
GroundTruth builtInGroundTruth();

// From a PGM: dark (below half the maximum) is occupied.
bool loadGroundTruth(const std::filesystem::path& path, GroundTruth& out, std::string& error);

// `count` cells drawn without repetition, in the order drawn; y is the truth (noise-free, Sec. VI-A).
std::vector<Sample> drawSamples(const GroundTruth& truth, std::size_t count, std::mt19937& rng);

// Samples from a CSV with columns row,col,y (header optional; y = 1 occupied, -1 free), in file order.
bool loadSamples(const std::filesystem::path& path, const GroundTruth& truth, std::vector<Sample>& out,
                 std::string& error);

}  // namespace ogf::paper2d
