// Fuzzes a navigation grid client on a stream of OGF_NAV_GRID payloads: the input is a sequence of records,
// each a 2-byte big-endian length and that many bytes of one LCM message. Each goes through the safe decode
// (messages::decodeMessage) and, when it decodes, into navigation::NavReceiver::accept, in order, as
// ogf-map-client --nav does. Nothing may crash, overflow or read out of bounds whatever the parts, sequence
// numbers, map ids, tiles and values claim; and the receiver's bookkeeping must hold after every message:
// an applied update moves the sequence forward, and the known columns and checksum it keeps per change are
// those of the grid it holds, counted afresh (while the tiles it holds lie within 64 × 64 tiles: grid() is
// a dense rectangle over the known columns); held tiles so far apart that the rectangle would be larger
// than a dense grid may be must make grid() a resource error, not an allocation.
#include <ogf/nav_grid_t.hpp>

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstdlib>

#include "ogf/messages/decode_message.hpp"
#include "ogf/navigation/nav_receiver.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A byte floor of 16 kB: a few tiles already go over it, so the dropping is fuzzed too.
  ogf::navigation::NavReceiver receiver(16, 16384);
  constexpr std::int64_t kSpan = 64;
  // The fewest columns a dense rectangle over tiles `d` apart holds along that axis: a column at the near
  // edge of each of the two outermost tiles.
  const auto fewestColumns = [](std::int64_t d) { return d == 0 ? 1 : (d - 1) * ogf::navigation::kTileSize + 2; };
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
      // What waits is within its bound after every message.
      if (receiver.heldBytes() > receiver.heldBytesLimit()) std::abort();
      std::int64_t lo_x = 0, lo_y = 0, hi_x = 0, hi_y = 0;
      const auto held = receiver.knownTiles();
      for (std::size_t t = 0; t < held.size(); ++t) {
        lo_x = t == 0 ? held[t].x : std::min<std::int64_t>(lo_x, held[t].x);
        hi_x = t == 0 ? held[t].x : std::max<std::int64_t>(hi_x, held[t].x);
        lo_y = t == 0 ? held[t].y : std::min<std::int64_t>(lo_y, held[t].y);
        hi_y = t == 0 ? held[t].y : std::max<std::int64_t>(hi_y, held[t].y);
      }
      if (hi_x - lo_x < kSpan && hi_y - lo_y < kSpan) {
        const auto grid = receiver.grid();
        if (!grid || grid->knownColumns() != receiver.knownColumns() || grid->checksum() != receiver.checksum())
          std::abort();
      } else if (fewestColumns(hi_x - lo_x) > ogf::navigation::kMaxDenseColumns / fewestColumns(hi_y - lo_y)) {
        const auto grid = receiver.grid();
        if (grid || grid.error().kind != ogf::ErrorKind::resource) std::abort();
      }
      (void)receiver.consistent();
    }
    at += take;
  }
  return 0;
}
