// The compact coding of a measurement set: difference from the previous key in one of four forms.
#include "ogf/persistence/measurement_coding.hpp"

#include <limits>

namespace ogf::persistence {
namespace {

constexpr unsigned kFormB = 0x80;
constexpr unsigned kFormC = 0xC0;
constexpr unsigned kFormD = 0xE0;
constexpr unsigned kExplicitY = 0x02;

std::uint64_t zigzag(std::int64_t v) {
  return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}

std::int64_t unzigzag(std::uint64_t u) { return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1); }

void putVarint(std::vector<std::byte>& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<std::byte>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<std::byte>(v));
}

// A varint of at most 5 bytes at `at` (advanced past it); false when it runs past `end` or is longer.
bool getVarint(const std::byte*& at, const std::byte* end, std::uint64_t& v) {
  v = 0;
  for (unsigned shift = 0; shift < 35; shift += 7) {
    if (at == end) return false;
    const auto b = static_cast<unsigned>(*at++);
    v |= static_cast<std::uint64_t>(b & 0x7F) << shift;
    if ((b & 0x80) == 0) return true;
  }
  return false;
}

}  // namespace

void encodeMeasurements(std::span<const Measurement> measurements, std::vector<std::byte>& out) {
  std::int64_t px = 0, py = 0, pz = 0;
  for (const Measurement& m : measurements) {
    const std::int64_t dx = m.key.x - px, dy = m.key.y - py, dz = m.key.z - pz;
    px = m.key.x;
    py = m.key.y;
    pz = m.key.z;
    const bool unit = m.y == 1 || m.y == -1;
    const unsigned o = m.y == 1 ? 1U : 0U;
    if (unit && dx == 0 && dy == 0 && dz >= 1 && dz <= 64) {
      out.push_back(static_cast<std::byte>((static_cast<unsigned>(dz - 1) << 1) | o));
    } else if (unit && dx == 0 && dy >= 1 && dy <= 32 && dz >= -128 && dz <= 127) {
      out.push_back(static_cast<std::byte>(kFormB | (static_cast<unsigned>(dy - 1) << 1) | o));
      out.push_back(static_cast<std::byte>(static_cast<std::uint8_t>(static_cast<std::int8_t>(dz))));
    } else if (unit && dx >= -8 && dx <= 7 && dy >= -8 && dy <= 7 && dz >= -8 && dz <= 7) {
      out.push_back(static_cast<std::byte>(kFormD | (static_cast<unsigned>(dx + 8) << 1) | o));
      out.push_back(
          static_cast<std::byte>((static_cast<unsigned>(dy + 8) << 4) | static_cast<unsigned>(dz + 8)));
    } else {
      out.push_back(static_cast<std::byte>(kFormC | (unit ? o : kExplicitY)));
      putVarint(out, zigzag(dx));
      putVarint(out, zigzag(dy));
      putVarint(out, zigzag(dz));
      if (!unit) out.push_back(static_cast<std::byte>(static_cast<std::uint8_t>(m.y)));
    }
  }
}

bool decodeMeasurements(std::span<const std::byte> bytes, std::size_t count, std::vector<Measurement>& out,
                        CodingVersion version) {
  out.clear();
  if (count > bytes.size()) return false;  // every form takes a byte at least
  out.reserve(count);
  const std::byte* at = bytes.data();
  const std::byte* const end = at + bytes.size();
  std::int64_t x = 0, y = 0, z = 0;
  constexpr std::int64_t kLow = std::numeric_limits<std::int32_t>::min();
  constexpr std::int64_t kHigh = std::numeric_limits<std::int32_t>::max();
  for (std::size_t i = 0; i < count; ++i) {
    if (at == end) return false;
    const auto tag = static_cast<unsigned>(*at++);
    std::int8_t value = (tag & 1U) != 0 ? 1 : -1;
    if ((tag & 0x80U) == 0) {
      z += static_cast<std::int64_t>(tag >> 1) + 1;
    } else if ((tag & 0xC0U) == kFormB) {
      if (at == end) return false;
      y += static_cast<std::int64_t>((tag >> 1) & 0x1FU) + 1;
      z += static_cast<std::int8_t>(static_cast<std::uint8_t>(*at++));
    } else if ((tag & 0xE0U) == kFormD && version == CodingVersion::k3) {
      if (at == end) return false;
      const auto steps = static_cast<unsigned>(*at++);
      x += static_cast<std::int64_t>((tag >> 1) & 0x0FU) - 8;
      y += static_cast<std::int64_t>(steps >> 4) - 8;
      z += static_cast<std::int64_t>(steps & 0x0FU) - 8;
    } else {
      if ((tag & ~(kExplicitY | 1U)) != kFormC || tag == (kFormC | kExplicitY | 1U)) return false;
      std::uint64_t ux = 0, uy = 0, uz = 0;
      if (!getVarint(at, end, ux) || !getVarint(at, end, uy) || !getVarint(at, end, uz)) return false;
      x += unzigzag(ux);
      y += unzigzag(uy);
      z += unzigzag(uz);
      if ((tag & kExplicitY) != 0) {
        if (at == end) return false;
        value = static_cast<std::int8_t>(static_cast<std::uint8_t>(*at++));
      }
    }
    if (x < kLow || x > kHigh || y < kLow || y > kHigh || z < kLow || z > kHigh) return false;
    out.push_back({{static_cast<std::int32_t>(x), static_cast<std::int32_t>(y), static_cast<std::int32_t>(z)}, value});
  }
  return at == end;
}

}  // namespace ogf::persistence
