#!/usr/bin/env bash
# Measures ogf-driver's CPU use at the sensor's live rate: replays a capture to it over UDP on loopback at
# the capture's own pace (about 754 data packets/s for a VLP-16) for SECONDS and reads the process's
# user+system CPU time from /proc/<pid>/stat over that window (start-up excluded).
# Usage: driver_cpu.sh BUILD_DIR CAPTURE [SECONDS [extra ogf-driver flags...]]
set -euo pipefail
build=${1:?build dir}; capture=${2:?capture file}; seconds=${3:-10}
port=$((40000 + $$ % 10000))
url="udpm://239.255.76.67:$((port + 2))?ttl=0"
"$build/bin/ogf-driver" "${@:4}" --bind-address 127.0.0.1 --data-port "$port" --position-port "$((port + 1))" \
  --lcm-url "$url" --log-level warn &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
sleep 0.5
cpu_ticks() { read -r -a stat < "/proc/$pid/stat"; echo $((stat[13] + stat[14])); }
before=$(cpu_ticks); t0=$(date +%s.%N)
python3 - "$capture" "$port" "$seconds" <<'PY'
import socket, struct, sys, time
path, port, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
data = open(path, 'rb').read()
records, o = [], 24
while o + 16 <= len(data):
    ts, tu, cl, ol = struct.unpack('<IIII', data[o:o + 16]); frame = data[o + 16:o + 16 + cl]; o += 16 + cl
    if len(frame) < cl: break
    ihl = (frame[14] & 15) * 4; udp = frame[14 + ihl:]
    dport = struct.unpack('>H', udp[2:4])[0]
    records.append((ts + tu * 1e-6, dport, udp[8:]))
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
start = time.monotonic(); sent = 0; lap = 0
t0 = records[0][0]; duration = records[-1][0] - t0 + 0.0013
while time.monotonic() - start < seconds:
    for t, dport, payload in records:
        due = start + lap * duration + (t - t0)
        delay = due - time.monotonic()
        if delay > 0: time.sleep(delay)
        s.sendto(payload, ('127.0.0.1', port if dport == 2368 else port + 1)); sent += 1
        if time.monotonic() - start >= seconds: break
    lap += 1
print(f"sent {sent} datagrams in {time.monotonic() - start:.1f} s")
PY
after=$(cpu_ticks); t1=$(date +%s.%N)
python3 -c "
cpu=($after-$before)/$(getconf CLK_TCK); wall=$t1-$t0
print(f'ogf-driver: {cpu:.2f} s CPU over {wall:.1f} s of live-rate input = {100*cpu/wall:.2f} % of one core')"
