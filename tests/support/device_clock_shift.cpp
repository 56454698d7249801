#include "support/device_clock_shift.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <vector>

namespace ogf::testing {
namespace {

constexpr std::int64_t kHourUs = 3'600'000'000LL;
constexpr std::size_t kGlobalHeader = 24;
constexpr std::size_t kRecordHeader = 16;
constexpr std::size_t kEthernet = 14;
constexpr std::size_t kUdp = 8;
constexpr std::size_t kDataPayload = 1206;
constexpr std::size_t kDataToh = 1200;
constexpr std::size_t kPositionToh = 198;

std::uint32_t le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
void putLe32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Calls visit(payload, size, record_header) for every UDP payload of the capture's bytes; returns an error
// or nullopt.
template <class Visit>
std::optional<std::string> forEachPayload(std::vector<std::uint8_t>& bytes, const std::string& name,
                                          Visit visit) {
  if (bytes.size() < kGlobalHeader || le32(bytes.data()) != 0xA1B2C3D4U) {
    return name + ": not a little-endian classic pcap (magic at offset 0)";
  }
  if (le32(bytes.data() + 20) != 1) return name + ": offset 20: link type is not Ethernet";
  for (std::size_t at = kGlobalHeader; at < bytes.size();) {
    if (bytes.size() - at < kRecordHeader)
      return name + ": offset " + std::to_string(at) + ": truncated record header";
    const std::size_t captured = le32(bytes.data() + at + 8);
    const std::size_t frame = at + kRecordHeader;
    if (bytes.size() - frame < captured) return name + ": offset " + std::to_string(at) + ": truncated frame";
    const std::uint8_t* f = bytes.data() + frame;
    if (captured >= kEthernet + 20 + kUdp && f[12] == 0x08 && f[13] == 0x00 && f[kEthernet + 9] == 17) {
      const std::size_t ip = static_cast<std::size_t>(f[kEthernet] & 0x0FU) * 4;
      const std::size_t payload = kEthernet + ip + kUdp;
      if (payload <= captured) visit(bytes.data() + frame + payload, captured - payload, bytes.data() + at);
    }
    at = frame + captured;
  }
  return std::nullopt;
}

std::optional<std::string> readAll(const std::filesystem::path& path, std::vector<std::uint8_t>& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return path.string() + ": cannot open";
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return std::nullopt;
}

std::optional<std::string> writeAll(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) return path.string() + ": cannot write";
  return std::nullopt;
}

}  // namespace

std::optional<std::string> copyWithDeviceClockShift(const std::filesystem::path& from,
                                                    const std::filesystem::path& to, std::int64_t shift_us) {
  std::vector<std::uint8_t> bytes;
  if (auto error = readAll(from, bytes)) return error;
  const auto shifted = [&](std::uint32_t toh) {
    return static_cast<std::uint32_t>(((static_cast<std::int64_t>(toh) + shift_us) % kHourUs + kHourUs) %
                                      kHourUs);
  };
  std::size_t data = 0;
  auto error = forEachPayload(bytes, from.string(), [&](std::uint8_t* payload, std::size_t size, std::uint8_t*) {
    if (size == kDataPayload) {
      putLe32(payload + kDataToh, shifted(le32(payload + kDataToh)));
      ++data;
    } else if (size == 512 || size == 554) {
      putLe32(payload + kPositionToh, shifted(le32(payload + kPositionToh)));
    }
  });
  if (error) return error;
  if (data == 0) return from.string() + ": no data packets";
  return writeAll(to, bytes);
}

std::optional<std::string> copyWithPause(const std::filesystem::path& from, const std::filesystem::path& to,
                                         std::int64_t after_data_packets, std::int64_t pause_us) {
  std::vector<std::uint8_t> bytes;
  if (auto error = readAll(from, bytes)) return error;
  std::int64_t data = 0;
  bool paused = false;
  auto error = forEachPayload(bytes, from.string(), [&](std::uint8_t* payload, std::size_t size, std::uint8_t* record) {
    if (size == kDataPayload && data++ == after_data_packets) paused = true;
    if (!paused) return;
    // The record's capture time (seconds, microseconds) and the sensor's counter both run on through the pause.
    const std::int64_t t = static_cast<std::int64_t>(le32(record)) * 1'000'000 + le32(record + 4) + pause_us;
    putLe32(record, static_cast<std::uint32_t>(t / 1'000'000));
    putLe32(record + 4, static_cast<std::uint32_t>(t % 1'000'000));
    const std::size_t toh = size == kDataPayload ? kDataToh : kPositionToh;
    if (size == kDataPayload || size == 512 || size == 554)
      putLe32(payload + toh, static_cast<std::uint32_t>((le32(payload + toh) + pause_us) % kHourUs));
  });
  if (error) return error;
  if (!paused) return from.string() + ": fewer than " + std::to_string(after_data_packets + 1) + " data packets";
  return writeAll(to, bytes);
}

std::optional<std::pair<std::int64_t, std::int64_t>> captureTimeSpan(const std::filesystem::path& capture) {
  std::vector<std::uint8_t> bytes;
  if (readAll(capture, bytes)) return std::nullopt;
  std::optional<std::pair<std::int64_t, std::int64_t>> span;
  const auto error = forEachPayload(bytes, capture.string(), [&](std::uint8_t*, std::size_t, std::uint8_t* record) {
    const std::int64_t t = static_cast<std::int64_t>(le32(record)) * 1'000'000 + le32(record + 4);
    if (!span) span.emplace(t, t);
    span->first = std::min(span->first, t);
    span->second = std::max(span->second, t);
  });
  return error ? std::nullopt : span;
}

std::optional<std::uint32_t> firstDataPacketToh(const std::filesystem::path& capture) {
  std::vector<std::uint8_t> bytes;
  if (readAll(capture, bytes)) return std::nullopt;
  std::optional<std::uint32_t> toh;
  const auto error = forEachPayload(bytes, capture.string(), [&](std::uint8_t* payload, std::size_t size, std::uint8_t*) {
    if (!toh && size == kDataPayload) toh = le32(payload + kDataToh);
  });
  return error ? std::nullopt : toh;
}

}  // namespace ogf::testing
