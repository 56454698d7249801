#include "view_process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/filter/map_file.hpp>
#include <ogf/map_delta_t.hpp>

#include <algorithm>

#include <csignal>
#include <cstdlib>
#include <regex>

#include "ogf/pipeline/published_cells.hpp"

namespace ogf::testing {

namespace fs = std::filesystem;

ViewProcess::ViewProcess(std::vector<std::string> args, const std::string& name, std::vector<std::string> wrapper)
    : log_path_((fs::temp_directory_path() / ("ogf-view-" + std::to_string(::getpid()) + "-" + name + ".log")).string()) {
  const char* program = std::getenv("OGF_VIEW_PROGRAM");
  args.insert(args.begin(), program ? std::string(program) : std::string(OGF_BIN_DIR) + "/ogf-view");
  args.insert(args.begin(), wrapper.begin(), wrapper.end());
  process_ = std::make_unique<ChildProcess>(args, log_path_);
}

ViewProcess::~ViewProcess() {
  process_->signal(SIGTERM);
  const auto rc = process_->wait(std::chrono::seconds(10));
  EXPECT_EQ(rc, 0) << process_->log();
  fs::remove(log_path_);
}

std::string ViewProcess::url() {
  if (!url_.empty()) return url_;
  const std::regex serving(R"(ogf-view: (http://[0-9.]+:[0-9]+/(\?token=[0-9a-f]+)?))");
  std::smatch m;
  for (int i = 0; i < 200; ++i) {
    const std::string text = process_->log();
    if (std::regex_search(text, m, serving)) return url_ = m[1];
    if (process_->wait(std::chrono::milliseconds(100))) break;
  }
  ADD_FAILURE() << "ogf-view did not start serving:\n" << process_->log();
  return "";
}

std::uint16_t ViewProcess::port() {
  const std::string u = url();
  const auto colon = u.rfind(':');
  return colon == std::string::npos ? 0 : static_cast<std::uint16_t>(std::stoi(u.substr(colon + 1)));
}

std::size_t writeBlockMap(const fs::path& path, int nx, int ny, int nz) {
  ogf::filter::FilterConfig cfg;
  cfg.resolution = 0.2;
  auto map = ogf::filter::BandedOgf::create(cfg);
  EXPECT_TRUE(map.ok());
  std::vector<ogf::Measurement> block;
  block.reserve(static_cast<std::size_t>(nx * ny * nz));
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z) block.push_back({{x, y, z}, ogf::Measurement::kOccupied});
  for (int i = 0; i < 3; ++i) map->update(block);
  EXPECT_TRUE(ogf::filter::saveMapFile(*map, path).ok());
  const auto cells = ogf::pipeline::publishedCellsOf(*map);
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), [](const auto& c) {
    return c.cell_class == ogf::map_delta_t::CLASS_OCCUPIED;
  }));
}

}  // namespace ogf::testing
