// Map file codec; saving writes the file atomically (ogf/common/atomic_file.hpp).
#include "ogf/filter/map_file.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "ogf/common/atomic_file.hpp"
#include "ogf/common/read_file.hpp"
#include "ogf/filter/map_checksum.hpp"

namespace ogf::filter {
namespace {

static_assert(std::endian::native == std::endian::little, "the map file codec assumes a little-endian host");

constexpr char kMagic[8] = {'O', 'G', 'F', '-', 'M', 'A', 'P', '\x1A'};

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  std::vector<std::uint8_t> bytes;
};

// Reads fields in order and remembers where it is, so an error names the offset and the field.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, std::string_view source) : bytes_(bytes), source_(source) {}
  template <class T>
  bool get(T& v, const char* field) {
    if (pos_ > bytes_.size() || bytes_.size() - pos_ < sizeof(T)) {
      error_ = fail(field, "file ends (truncated; " + std::to_string(bytes_.size()) + " bytes)");
      return false;
    }
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  Error fail(const char* field, const std::string& why) const {
    return Error::inputDamaged(std::string(source_) + ": offset " + std::to_string(pos_) + ", " + field + ": " + why);
  }
  std::size_t pos() const { return pos_; }
  void seek(std::size_t p) { pos_ = p; }
  const Error& error() const { return error_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::string_view source_;
  std::size_t pos_ = 0;
  Error error_;
};

struct Header {
  char magic[8] = {};
  std::uint32_t version = 0;
  std::uint32_t dimensions = 0;
  double resolution = 0.0;
  double sigma = 0.0;
  double amplitude = 0.0;
  double stencilRadius = 0.0;
  double taperSupport = 0.0;
  double occupiedThreshold = 0.0;
  double freeThreshold = 0.0;
  double skipTolerance = 0.0;
  double clampZ = 0.0;
  double freeClampZ = 0.0;  // version 2 on
  std::int32_t occupiedPriority = 0;  // version 3 on; version 1 and 2 maps filtered every measurement
  std::int32_t freeReleaseCount = 0;  // version 3 on
  std::int32_t manhattanRadius = 0;
  std::uint32_t blockSide = 0;
  std::uint32_t floatsPerCell = 0;
  std::uint32_t cellsPerBlock = 0;
  std::uint64_t blockCount = 0;
  std::uint64_t payloadChecksum = 0;
};

std::uint64_t checksumOf(std::span<const std::uint8_t> bytes) {
  MapChecksum sum;
  sum.add(std::as_bytes(bytes));
  return sum.value();
}

void writeHeaderFields(Writer& w, const Header& h) {
  for (char c : h.magic) {
    w.put(c);
  }
  w.put(h.version);
  w.put(h.dimensions);
  w.put(h.resolution);
  w.put(h.sigma);
  w.put(h.amplitude);
  w.put(h.stencilRadius);
  w.put(h.taperSupport);
  w.put(h.occupiedThreshold);
  w.put(h.freeThreshold);
  w.put(h.skipTolerance);
  w.put(h.clampZ);
  w.put(h.freeClampZ);
  w.put(h.occupiedPriority);
  w.put(h.freeReleaseCount);
  w.put(h.manhattanRadius);
  w.put(h.blockSide);
  w.put(h.floatsPerCell);
  w.put(h.cellsPerBlock);
  w.put(h.blockCount);
  w.put(h.payloadChecksum);
}

bool readHeaderFields(Reader& r, Header& h) {
  for (char& c : h.magic) {
    if (!r.get(c, "magic")) {
      return false;
    }
  }
  if (!(r.get(h.version, "version") && r.get(h.dimensions, "dimensions") && r.get(h.resolution, "resolution") &&
        r.get(h.sigma, "kernel sigma") && r.get(h.amplitude, "kernel amplitude") &&
        r.get(h.stencilRadius, "stencil radius") && r.get(h.taperSupport, "taper support") &&
        r.get(h.occupiedThreshold, "occupied threshold") && r.get(h.freeThreshold, "free threshold") &&
        r.get(h.skipTolerance, "skip tolerance") && r.get(h.clampZ, "clamp z"))) {
    return false;
  }
  // Version 1 has no free clamp: its free measurements used clampZ, which freeClampZ = 0 keeps.
  if (h.version >= 2 && !r.get(h.freeClampZ, "free clamp z")) {
    return false;
  }
  if (h.version >= 3 &&
      !(r.get(h.occupiedPriority, "occupied priority") && r.get(h.freeReleaseCount, "free release count"))) {
    return false;
  }
  return r.get(h.manhattanRadius, "stencil Manhattan radius") &&
         r.get(h.blockSide, "block side") && r.get(h.floatsPerCell, "floats per cell") &&
         r.get(h.cellsPerBlock, "cells per block") && r.get(h.blockCount, "block count") &&
         r.get(h.payloadChecksum, "payload checksum");
}

}  // namespace

std::uint64_t encodedMapBytes(const BandedOgf& map, std::uint64_t cells) {
  const std::uint64_t per_block = map.cellsPerBlock();
  const std::uint64_t blocks = (cells + per_block - 1) / per_block;
  return kMapFilePayloadAt + blocks * (3 * sizeof(std::int32_t) + map.floatsPerBlock() * sizeof(float) + per_block);
}

std::vector<std::uint8_t> encodeMap(const BandedOgf& map) {
  const FilterConfig& c = map.config();
  const std::vector<CellKey> keys = map.blockKeys();
  Header h;
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kMapFileVersion;
  h.dimensions = static_cast<std::uint32_t>(c.dimensions);
  h.resolution = c.resolution;
  h.sigma = *c.kernelSigma;
  h.amplitude = *c.kernelAmplitude;
  h.stencilRadius = *c.stencilRadius;
  h.taperSupport = *c.taperSupport;
  h.occupiedThreshold = c.occupiedThreshold;
  h.freeThreshold = c.freeThreshold;
  h.skipTolerance = c.skipTolerance;
  h.clampZ = c.clampZ;
  h.freeClampZ = c.freeClampZ;
  h.occupiedPriority = static_cast<std::int32_t>(c.occupiedPriority);
  h.freeReleaseCount = c.freeReleaseCount;
  h.manhattanRadius = c.stencilManhattanRadius;
  h.blockSide = kBlockSide;
  h.cellsPerBlock = c.dimensions == 3 ? 512U : 64U;
  h.floatsPerCell = static_cast<std::uint32_t>(map.floatsPerBlock() / h.cellsPerBlock);
  h.blockCount = keys.size();
  // One buffer of the file's exact size (a large map's file is the largest allocation a save makes): the
  // header with a placeholder checksum, the blocks, then the header again with both checksums.
  Writer out;
  out.bytes.reserve(encodedMapBytes(map, keys.size() * map.cellsPerBlock()));
  writeHeaderFields(out, h);
  out.put(std::uint64_t{0});
  const std::size_t payloadAt = out.bytes.size();
  for (const CellKey& key : keys) {
    out.put(key.x);
    out.put(key.y);
    out.put(key.z);
    const std::vector<float> values = map.blockValues(key);
    const auto* v = reinterpret_cast<const std::uint8_t*>(values.data());
    out.bytes.insert(out.bytes.end(), v, v + values.size() * sizeof(float));
    const auto marks = map.blockMarks(key);
    out.bytes.insert(out.bytes.end(), marks.begin(), marks.end());
  }
  h.payloadChecksum = checksumOf(std::span<const std::uint8_t>(out.bytes).subspan(payloadAt));
  Writer header;
  writeHeaderFields(header, h);
  header.put(checksumOf(header.bytes));
  std::copy(header.bytes.begin(), header.bytes.end(), out.bytes.begin());
  return std::move(out.bytes);
}

Result<BandedOgf> decodeMap(std::span<const std::uint8_t> bytes, std::string_view source, int threads) {
  Reader r(bytes, source);
  Header h;
  if (!readHeaderFields(r, h)) {
    return r.error();
  }
  const std::size_t headerEnd = r.pos();
  std::uint64_t headerChecksum = 0;
  if (!r.get(headerChecksum, "header checksum")) {
    return r.error();
  }
  r.seek(0);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) {
    return r.fail("magic", "not an ogf map file");
  }
  r.seek(8);
  if (h.version < 1 || h.version > kMapFileVersion) {
    return r.fail("version", std::to_string(h.version) + " (this build reads 1 to " + std::to_string(kMapFileVersion) + ")");
  }
  r.seek(headerEnd);
  if (headerChecksum != checksumOf(bytes.first(headerEnd))) {
    return r.fail("header checksum", "does not match the header (corrupted)");
  }
  FilterConfig config;
  config.dimensions = static_cast<int>(std::min<std::uint32_t>(h.dimensions, 1000));
  config.resolution = h.resolution;
  config.kernelSigma = h.sigma;
  config.kernelAmplitude = h.amplitude;
  config.stencilRadius = h.stencilRadius;
  config.stencilManhattanRadius = h.manhattanRadius;
  config.taperSupport = h.taperSupport;
  config.occupiedThreshold = h.occupiedThreshold;
  config.freeThreshold = h.freeThreshold;
  config.skipTolerance = h.skipTolerance;
  config.clampZ = h.clampZ;
  config.freeClampZ = h.freeClampZ;
  if (h.occupiedPriority != static_cast<std::int32_t>(OccupiedPriority::kScan) &&
      h.occupiedPriority != static_cast<std::int32_t>(OccupiedPriority::kMap)) {
    r.seek(96);  // the field's offset in version 3, the only version that has it
    return r.fail("occupied priority", std::to_string(h.occupiedPriority) + " (0 scan or 1 map)");
  }
  config.occupiedPriority = static_cast<OccupiedPriority>(h.occupiedPriority);
  config.freeReleaseCount = h.freeReleaseCount;
  // Mean and variance alone: compact covariance storage (a banded stencil keeps at least one covariance).
  config.covariance = h.floatsPerCell == 2 ? CovarianceStorage::kCompact : CovarianceStorage::kBanded;
  config.threads = std::clamp(threads, 1, 256);
  auto created = BandedOgf::create(config);
  if (!created) {
    return Error::inputDamaged(std::string(source) + ": header: " + created.error().message);
  }
  BandedOgf map = std::move(created).value();
  const std::size_t cellsPerBlock = config.dimensions == 3 ? 512U : 64U;
  const std::size_t floatsPerBlock = map.floatsPerBlock();
  if (h.blockSide != static_cast<std::uint32_t>(kBlockSide) || h.cellsPerBlock != cellsPerBlock ||
      static_cast<std::size_t>(h.floatsPerCell) * cellsPerBlock != floatsPerBlock) {
    return r.fail("block layout", "block side " + std::to_string(h.blockSide) + ", " +
                                      std::to_string(h.floatsPerCell) + " floats per cell do not match the stencil");
  }
  const std::size_t marksPerBlock = h.version >= 3 ? cellsPerBlock : 0;
  const std::size_t blockBytes = 3 * sizeof(std::int32_t) + floatsPerBlock * sizeof(float) + marksPerBlock;
  const std::size_t payloadStart = r.pos() + sizeof(std::uint64_t);
  const std::size_t payloadBytes = bytes.size() - payloadStart;
  if (h.blockCount > payloadBytes / blockBytes || h.blockCount * blockBytes != payloadBytes) {
    r.seek(payloadStart);
    return r.fail("block count", std::to_string(h.blockCount) + " blocks need " +
                                     std::to_string(h.blockCount * blockBytes) + " bytes, the file has " +
                                     std::to_string(payloadBytes) + (h.blockCount * blockBytes > payloadBytes
                                                                         ? " (truncated)"
                                                                         : " (trailing bytes)"));
  }
  if (h.payloadChecksum != checksumOf(bytes.subspan(payloadStart))) {
    r.seek(payloadStart);
    return r.fail("payload checksum", "does not match the blocks (corrupted)");
  }
  r.seek(payloadStart);
  std::vector<float> values(floatsPerBlock);
  std::vector<std::uint8_t> marks(marksPerBlock);
  for (std::uint64_t b = 0; b < h.blockCount; ++b) {
    CellKey key;
    if (!r.get(key.x, "block key") || !r.get(key.y, "block key") || !r.get(key.z, "block key")) {
      return r.error();
    }
    const std::size_t valuesAt = r.pos();
    std::memcpy(values.data(), bytes.data() + valuesAt, floatsPerBlock * sizeof(float));
    r.seek(valuesAt + floatsPerBlock * sizeof(float));
    for (std::size_t i = 0; i < floatsPerBlock; ++i) {
      const bool isVariance = i % h.floatsPerCell == 1;
      if (!std::isfinite(values[i]) || (isVariance && !(values[i] > 0.0F))) {
        r.seek(valuesAt + i * sizeof(float));
        return r.fail("block values", std::string(isVariance ? "variance" : "value") + " " +
                                          std::to_string(values[i]) + " is not " +
                                          (isVariance ? "positive" : "finite"));
      }
    }
    std::copy_n(bytes.data() + r.pos(), marksPerBlock, marks.begin());
    r.seek(r.pos() + marksPerBlock);
    if (auto st = map.restoreBlock(key, values, marks); !st) {
      r.seek(valuesAt - 3 * sizeof(std::int32_t));
      return r.fail("block key", st.error().message);
    }
  }
  return map;
}

Status saveMapFile(const BandedOgf& map, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = encodeMap(map);
  return writeFileAtomically(path, std::as_bytes(std::span(bytes)));
}

Result<BandedOgf> loadMapFile(const std::filesystem::path& path, int threads) {
  auto bytes = readWholeFile(path);
  if (!bytes) return bytes.error();
  const std::span<const std::uint8_t> raw(reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size());
  return decodeMap(raw, path.string(), threads);
}

}  // namespace ogf::filter
