#!/usr/bin/env bash
# What ogf costs on the wire, counted on the bus: bytes per second of a robot's scans (VELODYNE_SCAN,
# ogf.lidar_scan_t) and raw packets (VELODYNE_PACKETS), of the map delta stream (OGF_MAP_DELTA, what
# every map client receives: multicast sends one copy per link) and of the 2-D navigation grid
# (OGF_NAV_GRID, the nav.* defaults) at each resolution, with the publishing
# rule and budget of the configuration's defaults ("rule") and with every visible change sent unbounded
# ("all": deltas.probability_step 0, deltas.max_bytes_per_s 0).
#   scripts/wire.sh [--lab-duration S] [--drive-duration S] [--resolutions "0.2 0.1"] [--rules "all rule"]
#                   [--drives "lab loop"] [--out DIR] [--lcm-url URL]
#     lab:  scripts/run.sh's main job, the simulated lab (20 s by default);
#     loop: docs/performance.md's long drive, the street `loop` trajectory (600 s by default: 10 minutes).
#   Each run simulates the drive (ogf-sim), starts ogf-mapper (in memory), ogf-driver and ogf-map-client on
#   udpm over loopback, replays the drive in real time (ogf-replay), and counts every message on the bus
#   with lcm-logger writing into a pipe read by scripts/lcm_bytes.py (nothing is stored). Prints a Markdown
#   table: MB/s are the bytes of a channel divided by the seconds driven; "busiest s" is its largest
#   second; the delta messages counted are checked against those ogf-map-client received; "mapped" is
#   the scans ogf-mapper mapped of those it received; "client" says whether ogf-map-client (following
#   both with --nav) ended with the mapper's checksum of the map / of the grid;
#   "mapper cores" is ogf-mapper's CPU time (all its threads) from the drive's start until it mapped the
#   last scan, over the seconds driven: 0.5 is half a core, a mapper at twice real time.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$here/scripts/run-common.sh"
bin=${OGF_BUILD_DIR:-$here/build}/bin
out=$here/out/wire
lab_duration=20
drive_duration=600
resolutions="0.2 0.1"
rules="all rule"
drives="lab loop"
url="udpm://239.255.76.67:7691?ttl=0"
data_port=12369
position_port=18309
while [ $# -gt 0 ]; do
  case "$1" in
    --lab-duration) lab_duration=$2; shift 2 ;;
    --drive-duration) drive_duration=$2; shift 2 ;;
    --resolutions) resolutions=$2; shift 2 ;;
    --rules) rules=$2; shift 2 ;;
    --drives) drives=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --lcm-url) url=$2; shift 2 ;;
    -h|--help) sed -n '2,20p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "wire.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for tool in ogf-sim ogf-mapper ogf-driver ogf-map-client ogf-replay; do
  [ -x "$bin/$tool" ] || { echo "wire.sh: $bin/$tool missing: build first (scripts/build.sh)" >&2; exit 1; }
done
command -v lcm-logger >/dev/null || { echo "wire.sh: lcm-logger not found (scripts/install-deps.sh)" >&2; exit 1; }
bash "$here/scripts/multicast-loopback.sh" >/dev/null
mkdir -p "$out"
out=$(cd "$out" && pwd)

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

# CPU seconds (user + system, all threads) process $1 has used so far; nan when it has gone.
cpu_seconds() {
  awk -v tck="$(getconf CLK_TCK)" '{ printf "%.2f", ($14 + $15) / tck }' "/proc/$1/stat" 2>/dev/null || echo nan
}

# One run: drive $1 simulated in $2, resolution $3, rule $4, $5 seconds; appends its row to the table rows.
run() {
  local drive=$1 sim=$2 res=$3 rule=$4 seconds=$5
  local dir=$out/runs/$drive-$res-$rule
  rm -rf "$dir"; mkdir -p "$dir"
  extrinsic=$(sed -n 's/^sensor_to_body: {xyz: \(\[[^]]*\]\), quaternion_wxyz: \(\[[^]]*\]\)}.*/translation: \1, quaternion: \2/p' "$sim/sim.yaml")
  printf 'map:\n  resolution: %s\n  extrinsic: {%s}\n' "$res" "$extrinsic" > "$dir/mapper.yaml"
  if [ "$rule" = all ]; then printf 'deltas:\n  probability_step: 0\n  max_bytes_per_s: 0\n' >> "$dir/mapper.yaml"; fi

  mkfifo "$dir/bus.fifo"
  python3 "$here/scripts/lcm_bytes.py" "$dir/bus.fifo" --seconds "$seconds" --json > "$dir/bytes.json" &
  local counter=$!
  # A receive buffer that holds a burst of scans and keyframe parts: with the kernel's default the logger
  # loses large messages the mapper and the client receive.
  local sep='?'; case "$url" in *\?*) sep='&' ;; esac
  lcm-logger -q -f --lcm-url="${url}${sep}recv_buf_size=16777216" "$dir/bus.fifo" & local logger=$!; pids+=("$logger")
  "$bin/ogf-mapper" --lcm-url "$url" --in-memory --config "$dir/mapper.yaml" >"$dir/mapper.log" 2>&1 &
  local mapper=$!; pids+=("$mapper")
  "$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port "$data_port" \
    --position-port "$position_port" >"$dir/driver.log" 2>&1 &
  local driver=$!; pids+=("$driver")
  "$bin/ogf-map-client" --lcm-url "$url" --nav --progress >"$dir/client.log" 2>&1 &
  local client=$!; pids+=("$client")
  sleep 1
  local cpu_start; cpu_start=$(cpu_seconds "$mapper")
  "$bin/ogf-replay" --pcap "$sim/capture.pcap" --dest 127.0.0.1 --data-port "$data_port" \
    --position-port "$position_port" --speed 1 --odometry "$sim/odometry.csv" --lcm-url "$url" \
    --start-delay 1.5 > "$dir/replay.txt"
  sleep 0.5
  kill -TERM "$driver"; wait "$driver" || true
  wait_for_quiet_client "$dir/client.log"  # the mapper drains its queue
  echo "$cpu_start $(cpu_seconds "$mapper")" > "$dir/cpu.txt"
  kill -TERM "$client"; wait "$client" || true
  kill -TERM "$mapper"; wait "$mapper" || true
  kill -INT "$logger"; wait "$logger" || true
  pids=()
  wait "$counter"

  python3 - "$dir" "$drive" "$res" "$rule" "$seconds" >> "$out/rows.md" <<'PY'
import json, re, sys
d, drive, res, rule, seconds = sys.argv[1:]
b = json.load(open(f"{d}/bytes.json"))
def rate(ch, key="bytes_per_s"):
    return b.get(ch, {}).get(key, 0) / 1e6
mapper = open(f"{d}/mapper.log").read()
m = re.search(r"stopping: (\d+) scans in, (\d+) mapped", mapper)
mapped = f"{m.group(2)}/{m.group(1)}" if m else "?"
client = open(f"{d}/client.log").read().strip().splitlines()
last = ([l for l in client if l.startswith("map_id ")] or [""])[-1]
nav = ([l for l in client if l.startswith("nav_map_id ")] or [""])[-1]
c = re.search(r" consistent (\w+)", last)
n = re.search(r"nav_consistent (\w+)", nav)
got = re.search(r" messages (\d+)", last)
deltas = b.get("OGF_MAP_DELTA", {})
cpu_start, cpu_end = (float(x) for x in open(f"{d}/cpu.txt").read().split())
cores = (cpu_end - cpu_start) / float(seconds)
print(f"| {drive} ({seconds} s) | {res} | {rule} | {rate('VELODYNE_SCAN'):.2f} | {rate('VELODYNE_PACKETS'):.2f} | "
      f"{rate('OGF_MAP_DELTA'):.3f} | {rate('OGF_MAP_DELTA', 'peak_bytes_per_s'):.2f} | "
      f"{rate('OGF_NAV_GRID') * 1000:.1f} | {rate('OGF_NAV_GRID', 'peak_bytes_per_s') * 1000:.1f} | "
      f"{deltas.get('messages', 0)} / {got.group(1) if got else '?'} | {mapped} | {cores:.2f} | "
      f"{c.group(1) if c else '?'} / {n.group(1) if n else '?'} |")
PY
  tail -n 1 "$out/rows.md" >&2
}

: > "$out/rows.md"
for drive in $drives; do
  case "$drive" in
    lab) seconds=$lab_duration; sim_args=(--world lab) ;;
    loop) seconds=$drive_duration; sim_args=(--world street --trajectory loop) ;;
    *) echo "wire.sh: unknown drive '$drive' (lab or loop)" >&2; exit 2 ;;
  esac
  for res in $resolutions; do
    for rule in $rules; do
      # Simulated just before its replay, with the current time: the driver's GPS clock agrees with the host's.
      rm -rf "$out/sim-$drive"
      "$bin/ogf-sim" "${sim_args[@]}" --duration "$seconds" --out "$out/sim-$drive" \
        --start-utime "$(( $(date +%s) * 1000000 ))" > "$out/sim-$drive.log" 2>&1
      run "$drive" "$out/sim-$drive" "$res" "$rule" "$seconds"
    done
  done
done

echo
echo "| drive | cell m | deltas | VELODYNE_SCAN MB/s | VELODYNE_PACKETS MB/s | OGF_MAP_DELTA MB/s | OGF_MAP_DELTA busiest s MB | OGF_NAV_GRID kB/s | OGF_NAV_GRID busiest s kB | delta messages counted / client's | mapped | mapper cores | client map / grid |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
cat "$out/rows.md"
