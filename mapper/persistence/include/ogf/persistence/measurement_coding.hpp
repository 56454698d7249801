// The journal's compact coding of a measurement set (journal.hpp, record version 2). A scan's set comes in
// CellKey order, so most cells follow the one before in the same column (x, y) a few cells up in z, or in
// the next row of the same x: each measurement is coded by its difference from the one before (the first
// from (0, 0, 0)) in the shortest of three forms. Any set round-trips exactly, in any order, whatever its
// keys and y.
//
//   A  1 byte   0b0zzzzzzo           dx = dy = 0, dz = zzzzzz + 1 (1..64), y = o ? +1 : -1
//   B  2 bytes  0b10yyyyyo, i8 dz    dx = 0, dy = yyyyy + 1 (1..32), dz in [-128, 127], y = o ? +1 : -1
//   C  0b110000eo, varint zigzag(dx), varint zigzag(dy), varint zigzag(dz), then i8 y when e = 1 (o = 0);
//      else y = o ? +1 : -1. Varints are LEB128, at most 5 bytes each (differences of int32 coordinates).
#pragma once

#include <ogf/core/measurement.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ogf::persistence {

// The longest a coded measurement can be (form C with y): bounds a record's length from its count.
inline constexpr std::size_t kMaxCodedMeasurement = 1 + 3 * 5 + 1;

// Appends the coding of `measurements` to `out`.
void encodeMeasurements(std::span<const Measurement> measurements, std::vector<std::byte>& out);

// Decodes exactly `count` measurements that take exactly all of `bytes` into `out` (replacing it); false
// when the bytes are not such a coding (an unknown form, a key beyond int32, too few or too many bytes).
bool decodeMeasurements(std::span<const std::byte> bytes, std::size_t count, std::vector<Measurement>& out);

}  // namespace ogf::persistence
