// Fuzzes the journal's measurement coding (measurement_coding.hpp) with any bytes: the first two give the
// count, the rest are decoded. Every input must be refused or decoded to exactly that many measurements,
// which then code to bytes that decode to the same measurements; what coding version 2 reads, version 3
// reads the same. The same bytes read as 13-byte measurements must round-trip too.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include "ogf/persistence/measurement_coding.hpp"

namespace {

void roundTrip(const std::vector<ogf::Measurement>& set) {
  std::vector<std::byte> coded;
  ogf::persistence::encodeMeasurements(set, coded);
  if (coded.size() > set.size() * ogf::persistence::kMaxCodedMeasurement) std::abort();
  std::vector<ogf::Measurement> back;
  if (!ogf::persistence::decodeMeasurements(coded, set.size(), back) || back != set) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t count = static_cast<std::size_t>(data[0]) | static_cast<std::size_t>(data[1]) << 8;
  const auto bytes = std::as_bytes(std::span(data + 2, size - 2));
  std::vector<ogf::Measurement> decoded;
  if (ogf::persistence::decodeMeasurements(bytes, count, decoded)) {
    if (decoded.size() != count) std::abort();
    roundTrip(decoded);
  }
  // Version 2's forms are a subset of version 3's: what version 2 reads, version 3 reads the same.
  std::vector<ogf::Measurement> version2;
  if (ogf::persistence::decodeMeasurements(bytes, count, version2, ogf::persistence::CodingVersion::k2)) {
    if (!ogf::persistence::decodeMeasurements(bytes, count, decoded) || decoded != version2) std::abort();
  }
  std::vector<ogf::Measurement> raw;
  for (std::size_t at = 2; at + 13 <= size; at += 13) {
    std::int32_t k[3];
    std::memcpy(k, data + at, sizeof(k));
    raw.push_back({{k[0], k[1], k[2]}, static_cast<std::int8_t>(data[at + 12])});
  }
  roundTrip(raw);
  return 0;
}
