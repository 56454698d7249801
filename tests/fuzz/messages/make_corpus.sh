#!/usr/bin/env bash
# Regenerates the seed corpora of the message fuzzers from real encoded messages: runs the main job's
# pipeline briefly on udpm over loopback (ogf-sim, ogf-replay, ogf-driver with a short max range so scans
# stay small, ogf-mapper, ogf-map-client), logs the bus with lcm-logger, and cuts the log into
#   tests/fuzz/corpus/lcm_messages/<channel>-<n>      one message payload per file (each type, the smallest)
#   tests/fuzz/corpus/map_delta_stream/stream-<n>     OGF_MAP_DELTA payloads in order, 2-byte BE length each
#   tests/fuzz/corpus/nav_grid_stream/stream-<n>      OGF_NAV_GRID payloads likewise
# Usage: make_corpus.sh BIN_DIR (needs a multicast route over lo: scripts/multicast-loopback.sh).
set -euo pipefail
bin=${1:?usage: make_corpus.sh BIN_DIR}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)
work=$(mktemp -d /tmp/ogf-corpus-XXXXXX)
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
url="udpm://239.255.76.67:7693?ttl=0&recv_buf_size=8388608"
"$bin/ogf-sim" --world lab --duration 2 --out "$work/sim" --start-utime "$(( $(date +%s) * 1000000 ))" --log-level warn
lcm-logger --lcm-url="$url" "$work/bus.lcmlog" >/dev/null 2>&1 &
"$bin/ogf-mapper" --lcm-url "$url" --in-memory --log-level warn &
mapper=$!
"$bin/ogf-map-client" --lcm-url "$url" --duration 30 --log-level warn >/dev/null &
"$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port 12399 --position-port 18399 \
  --max-range 1.5 --log-level warn &
driver=$!
sleep 1
"$bin/ogf-replay" --pcap "$work/sim/capture.pcap" --dest 127.0.0.1 --data-port 12399 --position-port 18399 \
  --odometry "$work/sim/odometry.csv" --lcm-url "$url" --start-delay 0.5 >/dev/null
sleep 1
kill -TERM "$driver" "$mapper"; sleep 1.5
python3 - "$work/bus.lcmlog" "$here/tests/fuzz/corpus" <<'PY'
import os, struct, sys
log, out = sys.argv[1], sys.argv[2]
data = open(log, "rb").read()
at, events = 0, []
while at + 28 <= len(data):
    _, _, _, clen, dlen = struct.unpack_from(">IqqII", data, at)
    at += 28
    events.append((data[at:at + clen].decode(), data[at + clen:at + clen + dlen]))
    at += clen + dlen
single = os.path.join(out, "lcm_messages"); os.makedirs(single, exist_ok=True)
by_channel = {}
for ch, payload in events:
    by_channel.setdefault(ch, []).append(payload)
for ch, payloads in sorted(by_channel.items()):
    if ch.startswith("LCM_"):
        continue
    # The smallest message, and the smallest above a bare header (a scan with points, a delta with cells).
    by_size = sorted(payloads, key=len)
    seeds = [p for p in by_size[:1] if len(p) <= 32768] + [p for p in by_size if 400 < len(p) <= 32768][:1]
    for n, p in enumerate(seeds):
        open(os.path.join(single, f"{ch}-{n}"), "wb").write(p)
def write_streams(name, payloads, stride, budget):
    """Three seeds of consecutive payloads, each 2-byte BE length + payload, skipping what exceeds `budget`;
    seed n starts at payload n * stride."""
    folder = os.path.join(out, name); os.makedirs(folder, exist_ok=True)
    for n in range(3):
        chunk, total = b"", 0
        for p in payloads[n * stride:]:
            if total + len(p) > budget:
                continue
            chunk += struct.pack(">H", len(p)) + p
            total += len(p) + 2
        open(os.path.join(folder, f"stream-{n}"), "wb").write(chunk)
write_streams("map_delta_stream", by_channel.get("OGF_MAP_DELTA", []), 4, 16384)
write_streams("nav_grid_stream", by_channel.get("OGF_NAV_GRID", []), 3, 65536)
print({ch: len(p) for ch, p in by_channel.items()})
PY
