// Fuzzes the map file loader (decodeMap) with any bytes: as given, and with both checksums fixed up so the
// fuzzer reaches the header validation and the block parser behind them. Every input must be refused with
// an error or loaded whole; a loaded map must answer queries and re-encode.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "ogf/filter/map_checksum.hpp"
#include "ogf/filter/map_file.hpp"
#include "ogf/filter/map_queries.hpp"

namespace {

std::uint64_t checksumOf(std::span<const std::uint8_t> bytes) {
  ogf::filter::MapChecksum sum;
  sum.add(std::as_bytes(bytes));
  return sum.value();
}

void exercise(std::span<const std::uint8_t> bytes) {
  auto map = ogf::filter::decodeMap(bytes, "<fuzz>");
  if (!map) {
    return;
  }
  (void)ogf::filter::queryCell(*map, ogf::CellKey{0, 0, 0});
  (void)map->checksum();
  (void)ogf::filter::encodeMap(*map);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> raw(data, size);
  exercise(raw);
  if (size >= ogf::filter::kMapFilePayloadAt) {
    std::vector<std::uint8_t> fixed(data, data + size);
    const std::uint64_t payload = checksumOf(std::span(fixed).subspan(ogf::filter::kMapFilePayloadAt));
    std::memcpy(fixed.data() + ogf::filter::kMapFilePayloadChecksumAt, &payload, sizeof payload);
    const std::uint64_t header = checksumOf(std::span(fixed).first(ogf::filter::kMapFileHeaderChecksumAt));
    std::memcpy(fixed.data() + ogf::filter::kMapFileHeaderChecksumAt, &header, sizeof header);
    exercise(fixed);
  }
  return 0;
}
