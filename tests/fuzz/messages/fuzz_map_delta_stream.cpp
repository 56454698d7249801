// Fuzzes a map client on a stream of OGF_MAP_DELTA payloads: the input is a sequence of records, each a
// 2-byte big-endian length and that many bytes of one LCM message. Each goes through the safe decode
// (messages::decodeMessage) and, when it decodes, into MapReceiver::accept, in order, as ogf-map-client
// does. Nothing may crash, overflow or read out of bounds whatever the parts, sequence numbers, map ids
// and cells claim; and the receiver's own bookkeeping must hold after every message.
#include <ogf/map_delta_t.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ogf/delta/map_receiver.hpp"
#include "ogf/messages/decode_message.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A byte floor of 4 kB: a few parts of a few cells already go over it, so the dropping is fuzzed too.
  ogf::delta::MapReceiver receiver(16, 4096);
  std::size_t at = 0;
  while (size - at >= 2) {
    const std::size_t n = (std::size_t{data[at]} << 8) | data[at + 1];
    at += 2;
    const std::size_t take = n < size - at ? n : size - at;
    ogf::map_delta_t m;
    if (!ogf::messages::decodeMessage(data + at, take, m)) {
      const auto before = receiver.appliedSeq();
      const auto outcome = receiver.accept(m);
      // The applied sequence never goes back within one map, and an applied update is in sequence.
      if (outcome == ogf::delta::MapReceiver::Outcome::kApplied && receiver.appliedSeq() <= before) std::abort();
      if (!receiver.needsKeyframe() && receiver.appliedSeq() < 0) std::abort();
      // What waits is within its bound after every message.
      if (receiver.heldBytes() > receiver.heldBytesLimit()) std::abort();
      (void)receiver.consistent();
      (void)receiver.map().checksum();
    }
    at += take;
  }
  return 0;
}
