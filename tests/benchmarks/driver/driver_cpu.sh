#!/usr/bin/env bash
# Measures ogf-driver's CPU use at the sensor's live rate: replays a capture to it over UDP on loopback at
# the capture's own pace (about 754 data packets/s for a VLP-16) for SECONDS, then reads the process's
# user+system CPU time from /proc/<pid>/stat. Usage: driver_cpu.sh BUILD_DIR CAPTURE [SECONDS]
set -euo pipefail
build=${1:?build dir}; capture=${2:?capture file}; seconds=${3:-10}
port=$((40000 + $$ % 10000))
url="udpm://239.255.76.67:$((port + 2))?ttl=0"
"$build/bin/ogf-driver" --bind-address 127.0.0.1 --data-port "$port" --position-port "$((port + 1))" \
  --lcm-url "$url" --log-level warn &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
sleep 0.5
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
read -r -a stat < "/proc/$pid/stat"
ticks=$(getconf CLK_TCK)
start_ticks=${stat[21]}; utime=${stat[13]}; stime=${stat[14]}
uptime=$(cut -d' ' -f1 /proc/uptime)
python3 -c "
cpu=($utime+$stime)/$ticks; wall=$uptime-$start_ticks/$ticks
print(f'ogf-driver: {cpu:.2f} s CPU over {wall:.1f} s wall = {100*cpu/wall:.2f} % of one core')"
