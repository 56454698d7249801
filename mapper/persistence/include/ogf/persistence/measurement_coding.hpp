// The journal's compact coding of a measurement set (journal.hpp). A scan's set comes brick by brick
// (MeasurementSet), so most cells follow the one before in the same column (x, y) a few cells up in z, in
// the next row of the same x, or a few cells away in the same or the next brick: each measurement is
// coded by its difference from the one before (the first from (0, 0, 0)) in the shortest of four forms.
// Any set round-trips exactly, in any order, whatever its keys and y.
//
//   A  1 byte   0b0zzzzzzo           dx = dy = 0, dz = zzzzzz + 1 (1..64), y = o ? +1 : -1
//   B  2 bytes  0b10yyyyyo, i8 dz    dx = 0, dy = yyyyy + 1 (1..32), dz in [-128, 127], y = o ? +1 : -1
//   C  0b110000eo, varint zigzag(dx), varint zigzag(dy), varint zigzag(dz), then i8 y when e = 1 (o = 0);
//      else y = o ? +1 : -1. Varints are LEB128, at most 5 bytes each (differences of int32 coordinates).
//   D  2 bytes  0b111xxxxo, 0byyyyzzzz   dx = xxxx − 8, dy = yyyy − 8, dz = zzzz − 8 (each in [-8, 7]),
//      y = o ? +1 : -1. Only in codings of version 3 (journal records "JRC3"); version 2 has A, B and C.
#pragma once

#include <ogf/core/measurement.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ogf::persistence {

// The longest a coded measurement can be (form C with y): bounds a record's length from its count.
inline constexpr std::size_t kMaxCodedMeasurement = 1 + 3 * 5 + 1;

// Which forms a coding may hold: version 2 (A, B, C) or version 3 (A, B, C, D).
enum class CodingVersion { k2, k3 };

// Appends the coding (version 3) of `measurements` to `out`.
void encodeMeasurements(std::span<const Measurement> measurements, std::vector<std::byte>& out);

// Decodes exactly `count` measurements that take exactly all of `bytes` into `out` (replacing it); false
// when the bytes are not such a coding (an unknown form, a key beyond int32, too few or too many bytes).
bool decodeMeasurements(std::span<const std::byte> bytes, std::size_t count, std::vector<Measurement>& out,
                        CodingVersion version = CodingVersion::k3);

}  // namespace ogf::persistence
