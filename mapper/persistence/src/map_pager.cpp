#include "ogf/persistence/map_pager.hpp"

#include <ogf/filter/block_storage.hpp>
#include <ogf/filter/map_checksum.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <set>

#include "ogf/common/atomic_file.hpp"
#include "ogf/persistence/page_file.hpp"

namespace ogf::persistence {
namespace {

constexpr const char* kSuffix = ".ogfp";

CellKey regionOf(const CellKey& block, bool flat) {
  return {block.x >> MapPager::kRegionShift, block.y >> MapPager::kRegionShift,
          flat ? 0 : block.z >> MapPager::kRegionShift};
}

// The cells of a region: [lo, lo + side) on each axis (in a 2-D map the region at z = 0 holds z = 0).
constexpr int kRegionCellShift = MapPager::kRegionShift + 3;
static_assert(filter::kBlockSide == 1 << 3);
CellKey regionCellsLo(const CellKey& region) {
  return {region.x * (1 << kRegionCellShift), region.y * (1 << kRegionCellShift), region.z * (1 << kRegionCellShift)};
}
CellKey regionCellsHi(const CellKey& region) {
  return regionCellsLo(region) + CellKey{1 << kRegionCellShift, 1 << kRegionCellShift, 1 << kRegionCellShift};
}

// Why a page's published cells cannot be held for its region, or "" when they can: each must lie in the
// region (at z = 0 in a 2-D map), appear once, and carry a class and probability a delta could carry.
std::string strayPublished(const Page& page, bool flat) {
  const auto name = [](const delta::PublishedCell& c) {
    return "published cell " + std::to_string(c.key.x) + "," + std::to_string(c.key.y) + "," + std::to_string(c.key.z);
  };
  std::vector<CellKey> keys;
  keys.reserve(page.published.size());
  for (const delta::PublishedCell& c : page.published) {
    if (!(regionOf(filter::blockKeyOf(c.key), flat) == page.region) || (flat && c.key.z != 0))
      return name(c) + " lies outside the page's region";
    keys.push_back(c.key);
    if (c.cell_class < ogf::map_delta_t::CLASS_FREE || c.cell_class > ogf::map_delta_t::CLASS_OCCUPIED ||
        c.probability < 0 || c.probability > delta::kProbabilityScale)
      return name(c) + " has class " + std::to_string(c.cell_class) + " and probability " +
             std::to_string(c.probability) + ", which no delta carries";
  }
  std::sort(keys.begin(), keys.end());
  const auto twice = std::adjacent_find(keys.begin(), keys.end());
  if (twice != keys.end()) return name({*twice}) + " is named twice";
  return "";
}

// The number in a page file's name ("r<x>_<y>_<z>-<n>.ogfp"), or 0 when it is not one.
std::uint64_t pageNumber(const std::string& name) {
  const auto dash = name.rfind('-');
  if (name.size() < 6 || name.compare(name.size() - 5, 5, kSuffix) != 0 || dash == std::string::npos) return 0;
  try {
    return std::stoull(name.substr(dash + 1, name.size() - 5 - dash - 1));
  } catch (...) {
    return 0;
  }
}

std::vector<std::byte> readAll(const std::filesystem::path& path, std::string& why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0) {
    why = std::string("cannot read the page: ") + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    return {};
  }
  std::vector<std::byte> bytes(static_cast<std::size_t>(st.st_size));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // a file cut short reads as a truncated page
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

// Writes `bytes` to a new file at `path`, not flushed: the writeback is started (sync_file_range, which
// does not wait), so the fsync of sync() at the next snapshot finds it done. Flushing 900 pages of 110 kB
// written a few milliseconds apart took 0.41 s without the hint and 0.08-0.11 s with it on the README's
// machine; the hint costs each write about 0.25 ms.
Status writeNewFile(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return Error::system(path.string() + ": cannot create the page");
  if (const std::size_t done = writeAll(fd, bytes); done != bytes.size()) {
    const int why = errno;
    ::close(fd);
    ::unlink(path.c_str());
    return Error::system(path.string() + ": write failed at offset " + std::to_string(done), why);
  }
  // A hint only: an error here (a file system without it) leaves the flush to sync(), as without it.
  (void)::sync_file_range(fd, 0, 0, SYNC_FILE_RANGE_WRITE);
  if (::close(fd) != 0) {
    const int why = errno;
    ::unlink(path.c_str());
    return Error::system(path.string() + ": close failed", why);
  }
  return okStatus();
}

Status flushFile(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) return Error::system(path.string() + ": cannot open to flush");
  const int rc = ::fsync(fd);
  const int why = rc != 0 ? errno : 0;
  ::close(fd);
  if (rc != 0) return Error::system(path.string() + ": fsync failed", why);
  return okStatus();
}

// The page at `path`, else the reason.
Result<Page> readPage(const std::filesystem::path& path) {
  std::string why;
  const auto bytes = readAll(path, why);
  if (!why.empty()) return Error::io(path.string() + ": " + why);
  return decodePage(bytes, path.string());
}

// The same when it holds blocks of `map`'s layout.
Result<Page> readPage(const std::filesystem::path& path, const filter::BandedOgf& map) {
  auto page = readPage(path);
  if (!page) return page.error();
  if (page->floats_per_block != map.storedFloatsPerBlock() || page->cells_per_block != map.cellsPerBlock())
    return Error::inputDamaged(path.string() + ": offset 28: blocks of " + std::to_string(page->floats_per_block) +
                               " floats and " + std::to_string(page->cells_per_block) + " cells, the map stores " +
                               std::to_string(map.storedFloatsPerBlock()) + " and " + std::to_string(map.cellsPerBlock()));
  return page;
}

}  // namespace

Result<MapPager> MapPager::open(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error::system(dir.string() + ": cannot create the page directory", ec);
  std::uint64_t next = 1;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    next = std::max(next, pageNumber(entry.path().filename().string()) + 1);
  }
  if (ec) return Error::system(dir.string() + ": cannot list the page directory", ec);
  return MapPager(dir, next);
}

std::vector<PageDamage> MapPager::adopt(std::span<const std::string> names, const filter::BandedOgf& map) {
  std::vector<PageDamage> damage;
  for (const std::string& name : names) {
    const std::filesystem::path path = dir_ / name;
    auto page = readPage(path, map);
    if (!page) {
      damage.push_back({path, page.error().message});
      continue;
    }
    PagedRegion region{name, {}, 0, page->has_published, false, {}};
    for (const delta::PublishedCell& c : page->published) region.published.checksum += delta::cellChecksum(c);
    region.published.cells = page->published.size();
    const bool flat = map.config().dimensions == 2;
    std::string stray;
    for (const PageBlock& b : page->blocks) {
      if (!(regionOf(b.key, flat) == page->region) || (flat && b.key.z != 0))
        stray = "block " + std::to_string(b.key.x) + "," + std::to_string(b.key.y) + "," + std::to_string(b.key.z) +
                " lies outside the page's region";
      region.blocks.sum += filter::blockChecksum(b.key, b.stored, b.marks);
      ++region.blocks.blocks;
    }
    if (stray.empty()) stray = strayPublished(*page, flat);
    if (!stray.empty()) {
      damage.push_back({path, path.string() + ": " + stray});
      continue;
    }
    std::error_code ec;
    region.bytes = std::filesystem::file_size(path, ec);
    if (paged_.contains(page->region)) {
      damage.push_back({path, path.string() + ": region " + std::to_string(page->region.x) + "," +
                                  std::to_string(page->region.y) + "," + std::to_string(page->region.z) +
                                  " is named twice"});
      continue;
    }
    remember(page->region, std::move(region));
  }
  return damage;
}

void MapPager::remember(const CellKey& region, PagedRegion paged) {
  held_.sum += paged.blocks.sum;
  held_.blocks += paged.blocks.blocks;
  bytes_out_ += paged.bytes;
  paged_.emplace(region, std::move(paged));
}

void MapPager::forget(const CellKey& region) {
  const auto it = paged_.find(region);
  held_.sum -= it->second.blocks.sum;
  held_.blocks -= it->second.blocks.blocks;
  bytes_out_ -= it->second.bytes;
  paged_.erase(it);
}

void MapPager::load(filter::BandedOgf& map, const CellKey& region, std::vector<PageDamage>& damage,
                    delta::PublishedMap* published) {
  const PagedRegion paged = paged_.at(region);
  const std::filesystem::path path = dir_ / paged.file;
  forget(region);
  const bool withPublished = published != nullptr && paged.publishedOut;
  auto page = readPage(path, map);
  if (!page) {
    damage.push_back({path, page.error().message});
    if (withPublished) published->forget(paged.published);
    return;
  }
  for (const PageBlock& b : page->blocks) {
    if (auto st = map.restoreStoredBlock(b.key, b.stored, b.marks); !st) {
      damage.push_back({path, path.string() + ": " + st.error().message});
    }
  }
  if (withPublished) published->restore(page->published);
  ++pages_read_;
}

std::vector<PageDamage> MapPager::bringInUnpublished(filter::BandedOgf& map) {
  std::vector<PageDamage> damage;
  std::vector<CellKey> regions;
  for (const auto& [region, paged] : paged_)
    if (!paged.publishedKnown) regions.push_back(region);
  std::sort(regions.begin(), regions.end());
  for (const CellKey& region : regions) load(map, region, damage, nullptr);
  return damage;
}

void MapPager::holdPublished(delta::PublishedMap& published) {
  for (auto& [region, paged] : paged_) {
    if (!paged.publishedKnown || paged.publishedOut) continue;
    published.hold(paged.published);
    paged.publishedOut = true;
  }
}

std::vector<std::filesystem::path> MapPager::heldPublishedPages() const {
  std::vector<std::filesystem::path> pages;
  for (const auto& [region, paged] : paged_) {
    if (paged.publishedOut && paged.published.cells != 0) pages.push_back(dir_ / paged.file);
  }
  return pages;
}

Result<std::vector<delta::PublishedCell>> MapPager::publishedCellsOf(const std::filesystem::path& path) {
  auto page = readPage(path);
  if (!page) return page.error();
  return std::move(page->published);
}

std::vector<PageDamage> MapPager::bringIn(filter::BandedOgf& map, std::span<const Measurement> measurements,
                                          delta::PublishedMap* published) {
  std::vector<PageDamage> damage;
  if (paged_.empty()) return damage;
  const bool flat = map.config().dimensions == 2;
  std::set<CellKey> wanted;
  CellKey lastLo{}, lastHi{};
  bool first = true;
  for (const Measurement& m : measurements) {
    // The blocks one block around the measured one, and the regions they lie in: mostly the same few
    // regions as for the measurement before.
    const CellKey block = filter::blockKeyOf(m.key);
    const CellKey lo = regionOf(block - CellKey{1, 1, 1}, flat);
    const CellKey hi = regionOf(block + CellKey{1, 1, 1}, flat);
    if (!first && lo == lastLo && hi == lastHi) continue;
    first = false;
    lastLo = lo;
    lastHi = hi;
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
          if (paged_.contains(CellKey{x, y, z})) wanted.insert(CellKey{x, y, z});
  }
  for (const CellKey& region : wanted) load(map, region, damage, published);
  return damage;
}

std::vector<PageDamage> MapPager::bringInBox(filter::BandedOgf& map, const std::array<double, 3>& lo,
                                             const std::array<double, 3>& hi, delta::PublishedMap* published) {
  std::vector<PageDamage> damage;
  if (paged_.empty()) return damage;
  const bool flat = map.config().dimensions == 2;
  const double res = map.config().resolution;
  // Cell i spans [i·res, (i+1)·res); one cell of margin either side for rounding.
  const auto regionAt = [&](const std::array<double, 3>& p, int margin) {
    CellKey cell;
    int* c[3] = {&cell.x, &cell.y, &cell.z};
    for (std::size_t a = 0; a < 3; ++a) {
      const double v = std::clamp(std::floor(p[a] / res), -1e9, 1e9);
      *c[a] = static_cast<int>(v) + margin;
    }
    return regionOf(filter::blockKeyOf(cell), flat);
  };
  if (!(std::isfinite(lo[0]) && std::isfinite(lo[1]) && std::isfinite(lo[2]) && std::isfinite(hi[0]) &&
        std::isfinite(hi[1]) && std::isfinite(hi[2])))
    return damage;
  const CellKey a = regionAt(lo, -1);
  const CellKey b = regionAt(hi, 1);
  std::vector<CellKey> wanted;
  for (const auto& [region, paged] : paged_) {
    if (region.x >= a.x && region.x <= b.x && region.y >= a.y && region.y <= b.y && region.z >= a.z &&
        region.z <= b.z)
      wanted.push_back(region);
  }
  std::sort(wanted.begin(), wanted.end());
  for (const CellKey& region : wanted) load(map, region, damage, published);
  return damage;
}

std::vector<PageDamage> MapPager::bringInAll(filter::BandedOgf& map, delta::PublishedMap* published) {
  std::vector<PageDamage> damage;
  std::vector<CellKey> regions;
  for (const auto& [region, paged] : paged_) regions.push_back(region);
  std::sort(regions.begin(), regions.end());
  for (const CellKey& region : regions) load(map, region, damage, published);
  return damage;
}

Status MapPager::sendAway(filter::BandedOgf& map, const std::array<double, 3>& position, double distance_m,
                          delta::PublishedMap* published) {
  const bool flat = map.config().dimensions == 2;
  const double side = regionSide(map.config().resolution);
  if (looked_ && pages_read_ == read_at_look_) {
    const double moved = std::hypot(position[0] - last_position_[0], position[1] - last_position_[1],
                                    flat ? 0.0 : position[2] - last_position_[2]);
    if (moved < side / 4) return okStatus();
  }
  looked_ = true;
  last_position_ = position;
  read_at_look_ = pages_read_;
  // The resident blocks of every region whose nearest point is beyond the distance.
  std::unordered_map<CellKey, std::vector<CellKey>, CellKeyHash> far;
  map.forEachBlockKey([&](const CellKey& block) {
    const CellKey region = regionOf(block, flat);
    const int r[3] = {region.x, region.y, region.z};
    double d2 = 0.0;
    for (int a = 0; a < (flat ? 2 : 3); ++a) {
      const double lo = r[a] * side;
      const double gap = std::max({lo - position[static_cast<std::size_t>(a)], 0.0,
                                   position[static_cast<std::size_t>(a)] - (lo + side)});
      d2 += gap * gap;
    }
    if (d2 > distance_m * distance_m) far[region].push_back(block);
  });
  std::vector<CellKey> regions;
  for (const auto& [region, blocks] : far) regions.push_back(region);
  std::sort(regions.begin(), regions.end());
  for (const CellKey& region : regions) {
    std::vector<CellKey>& keys = far[region];
    std::sort(keys.begin(), keys.end());
    Page page;
    page.region = region;
    page.floats_per_block = static_cast<std::uint32_t>(map.storedFloatsPerBlock());
    page.cells_per_block = static_cast<std::uint32_t>(map.cellsPerBlock());
    PagedRegion paged;
    for (const CellKey& key : keys) {
      const auto stored = map.storedValues(key);
      const auto marks = map.blockMarks(key);
      page.blocks.push_back({key, {stored.begin(), stored.end()}, {marks.begin(), marks.end()}});
      paged.blocks.sum += map.blockHash(key);
      ++paged.blocks.blocks;
    }
    if (published != nullptr) page.published = published->cellsIn(regionCellsLo(region), regionCellsHi(region));
    paged.file = "r" + std::to_string(region.x) + "_" + std::to_string(region.y) + "_" + std::to_string(region.z) +
                 "-" + std::to_string(next_++) + kSuffix;
    const auto bytes = encodePage(page);
    if (auto st = writeNewFile(dir_ / paged.file, bytes); !st) return st;
    unsynced_.push_back(paged.file);
    paged.bytes = bytes.size();
    for (const CellKey& key : keys) map.eraseBlock(key);
    if (published != nullptr) {
      paged.published = published->evict(regionCellsLo(region), regionCellsHi(region));
      paged.publishedKnown = true;
      paged.publishedOut = true;
    }
    remember(region, std::move(paged));
    ++pages_written_;
  }
  return okStatus();
}

Status MapPager::sync() {
  const PageFlush flush = takeUnsynced();
  auto st = flushPages(flush);
  if (!st) giveBackUnsynced(flush);
  return st;
}

MapPager::PageFlush MapPager::takeUnsynced() {
  PageFlush flush{dir_, {}};
  if (unsynced_.empty()) return flush;
  std::set<std::string> out;
  for (const auto& [region, paged] : paged_) out.insert(paged.file);
  for (const std::string& name : unsynced_) {
    if (out.contains(name)) flush.names.push_back(name);  // else back in memory: no snapshot will name it
  }
  unsynced_.clear();
  return flush;
}

Status MapPager::flushPages(const PageFlush& flush) {
  if (flush.names.empty()) return okStatus();
  for (const std::string& name : flush.names) {
    if (auto st = flushFile(flush.dir / name, O_RDONLY); !st) return st;
  }
  return flushFile(flush.dir, O_RDONLY | O_DIRECTORY);
}

void MapPager::giveBackUnsynced(const PageFlush& flush) {
  unsynced_.insert(unsynced_.end(), flush.names.begin(), flush.names.end());
}

std::vector<std::string> MapPager::files() const {
  std::vector<std::string> names;
  names.reserve(paged_.size());
  for (const auto& [region, paged] : paged_) names.push_back(paged.file);
  std::sort(names.begin(), names.end());
  return names;
}

std::size_t MapPager::collect(std::span<const std::string> keep) {
  std::set<std::string> named(keep.begin(), keep.end());
  for (const auto& [region, paged] : paged_) named.insert(paged.file);
  std::size_t removed = 0;
  std::error_code ec;
  std::vector<std::filesystem::path> doomed;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    const std::string name = entry.path().filename().string();
    if (pageNumber(name) != 0 && !named.contains(name)) doomed.push_back(entry.path());
  }
  for (const auto& path : doomed) {
    if (std::filesystem::remove(path, ec)) ++removed;
  }
  return removed;
}

}  // namespace ogf::persistence
