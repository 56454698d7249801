// A publisher of OGF_NAV_GRID for the Python NavClient test: the 2-D grid of a map file's default band,
// streamed over real LCM with navigation::NavStream as the mapper streams it: the map's cells arrive in
// `batches` updates (changed tiles only), 0.2 s apart, and every map_request_t on OGF_NAV_REQUEST is
// answered with a keyframe. After the last update it prints one line,
//   published seq <n> checksum <hex> known_columns <n> width <n> height <n>
// (width and height 0 when the grid is too wide for a dense rectangle), then keeps answering requests
// until `seconds` have passed since it started. MAP_FILE `far-apart` publishes instead two occupied columns
// 2 000 000 columns apart along x and 400 along y, as a forged or damaged stream could place them.
// Usage: ogf_test_nav_publisher LCM_URL MAP_FILE|far-apart SECONDS [BATCHES]; exit 2 on bad usage or input.
#include <lcm/lcm-cpp.hpp>

#include <ogf/map_request_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/navigation/nav_projection.hpp"
#include "ogf/navigation/nav_stream.hpp"
#include "ogf/transport/subscriber.hpp"

namespace {

std::int64_t nowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void publish(lcm::LCM& lcm, const std::vector<ogf::nav_grid_t>& messages) {
  for (const auto& m : messages) lcm.publish("OGF_NAV_GRID", &m);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s LCM_URL MAP_FILE SECONDS [BATCHES]\n", argv[0]);
    return 2;
  }
  const std::string url = argv[1];
  const double seconds = std::atof(argv[3]);
  const int batches = argc > 4 ? std::max(1, std::atoi(argv[4])) : 4;
  ogf::map_formats::MapCells cells;
  if (std::string(argv[2]) == "far-apart") {
    cells.cells = {{{-1000000, -200, 3}, 0.9, 1, 0.01f}, {{1000000, 200, 3}, 0.9, 1, 0.01f}};
  } else {
    auto loaded = ogf::map_formats::loadOgfMap(argv[2]);
    if (!loaded) {
      std::fprintf(stderr, "%s\n", loaded.error().message.c_str());
      return 2;
    }
    cells = ogf::map_formats::collectCells(loaded->map);
  }
  auto projection = ogf::navigation::NavProjection::create(cells.resolution, ogf::navigation::NavBand{});
  if (!projection) {
    std::fprintf(stderr, "%s\n", projection.error().message.c_str());
    return 2;
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "cannot join %s\n", url.c_str());
    return 2;
  }
  ogf::navigation::NavStream stream(/*map_id=*/nowUtime());
  int requests = 0;
  ogf::transport::Subscriber<ogf::map_request_t> requests_sub(
      lcm, "OGF_NAV_REQUEST",
      [&](const ogf::map_request_t&, const lcm::ReceiveBuffer&, const std::string&) {
        ++requests;
        publish(lcm, stream.keyframe(nowUtime(), *projection));
      },
      [](const std::string&, std::size_t, const std::string&) {});

  const auto start = std::chrono::steady_clock::now();
  const auto handleFor = [&](double s) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s);
    while (std::chrono::steady_clock::now() < until) lcm.handleTimeout(20);
  };
  const std::size_t n = cells.cells.size();
  const auto parts = static_cast<std::size_t>(batches);
  for (std::size_t b = 0; b < parts; ++b) {
    for (std::size_t i = n * b / parts; i < n * (b + 1) / parts; ++i) {
      const auto& c = cells.cells[i];
      projection->update(ogf::navigation::CellState{c.key, c.probability, c.cell_class, c.variance});
    }
    const auto tiles = projection->refresh();
    publish(lcm, stream.update(nowUtime(), *projection, tiles));
    handleFor(0.2);
  }
  const auto grid = projection->grid();
  std::printf("published seq %lld checksum %016llx known_columns %zu width %d height %d\n",
              static_cast<long long>(stream.seq()), static_cast<unsigned long long>(projection->checksum()),
              projection->knownColumns(), grid ? grid->width : 0, grid ? grid->height : 0);
  std::fflush(stdout);
  while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) lcm.handleTimeout(50);
  std::fprintf(stderr, "keyframe requests answered: %d\n", requests);
  return 0;
}
