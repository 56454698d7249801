// Fuzzes a navigation grid client on a stream of OGF_NAV_GRID payloads: the input is a sequence of records,
// each a 2-byte big-endian length and that many bytes of one LCM message. Each goes through the safe decode
// (messages::decodeMessage) and, when it decodes, into navigation::NavReceiver::accept, in order, as
// ogf-map-client --nav does. Nothing may crash, overflow or read out of bounds whatever the parts, sequence
// numbers, map ids, tiles and values claim; and the receiver's bookkeeping must hold after every message:
// an applied update moves the sequence forward, and the known columns and checksum it keeps per change are
// those of the grid it holds, counted afresh (while every tile seen lies within 64 × 64 tiles: grid() is a
// dense rectangle over the known columns, and tiles far apart would make it as large as they claim).
#include <ogf/nav_grid_t.hpp>

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstdlib>

#include "ogf/messages/decode_message.hpp"
#include "ogf/navigation/nav_receiver.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ogf::navigation::NavReceiver receiver(16);
  constexpr std::int64_t kSpan = 64;
  std::int64_t lo_x = INT64_MAX, lo_y = INT64_MAX, hi_x = INT64_MIN, hi_y = INT64_MIN;
  std::size_t at = 0;
  while (size - at >= 2) {
    const std::size_t n = (std::size_t{data[at]} << 8) | data[at + 1];
    at += 2;
    const std::size_t take = n < size - at ? n : size - at;
    ogf::nav_grid_t m;
    if (!ogf::messages::decodeMessage(data + at, take, m)) {
      const auto before = receiver.appliedSeq();
      const auto outcome = receiver.accept(m);
      if (outcome == ogf::navigation::NavReceiver::Outcome::kApplied && receiver.appliedSeq() <= before) std::abort();
      if (!receiver.needsKeyframe() && receiver.appliedSeq() < 0) std::abort();
      for (std::size_t t = 0; t < m.tile_x.size() && t < m.tile_y.size(); ++t) {
        lo_x = std::min<std::int64_t>(lo_x, m.tile_x[t]);
        hi_x = std::max<std::int64_t>(hi_x, m.tile_x[t]);
        lo_y = std::min<std::int64_t>(lo_y, m.tile_y[t]);
        hi_y = std::max<std::int64_t>(hi_y, m.tile_y[t]);
      }
      // No tile yet (the bounds still at their extremes, whose difference would overflow): nothing to span.
      const bool noTile = hi_x < lo_x;
      if (noTile || (hi_x - lo_x < kSpan && hi_y - lo_y < kSpan)) {
        const auto grid = receiver.grid();
        if (grid.knownColumns() != receiver.knownColumns() || grid.checksum() != receiver.checksum()) std::abort();
      }
      (void)receiver.consistent();
    }
    at += take;
  }
  return 0;
}
