#!/usr/bin/env bash
# The README's main job: installs what is missing, builds, then drives ogf end to end on this host.
#   scripts/run.sh [--out DIR] [--speed X] [--duration S] [--world PRESET|FILE] [--lcm-url URL]
#                  [--view-port PORT] [--view-wait S]
#     simulates a VLP-16 on a robot in a known world (ogf-sim), starts ogf-mapper and ogf-driver as real
#     processes on LCM udpm over loopback, follows the map and its 2-D grid with ogf-map-client and ogf-view (the map in a
#     browser at http://127.0.0.1:PORT/; --view-wait S waits S seconds after printing the address
#     so a browser can be opened before the drive starts), replays the capture onto UDP
#     and the odometry onto LCM with ogf-replay, stops the daemons with SIGTERM (the mapper writes its final
#     snapshot), and scores the map against the ground truth and an OctoMap from the same rays (ogf-eval).
#   scripts/run.sh --rig front-rear|FILE [--out DIR] [--speed X] [--duration S] [--world PRESET|FILE]
#   scripts/run.sh --robots N [--out DIR] [--speed X] [--duration S] [--world PRESET|FILE]
#     several lidars on one robot (a rig file, or the preset front-rear), or N robots in one world: one
#     ogf-driver per sensor, one ogf-mapper for all (its sources: list), one ogf-map-client per robot, and the
#     shared map scored beside each source's map alone (scripts/run-sources.sh).
#   scripts/run.sh --pcap FILE [--out DIR]
#     maps a real capture of a static sensor instead: ogf-map --static (fixed pose, offline, the same
#     ScanMapper as the daemon); no ground truth, so the scores are how the map and an OctoMap of the same
#     returns hold those returns (scripts/run-pcap.sh).
# Each run takes its own bus and ports: the LCM port 7689+k, the sensor's ports 12368+2k and 18308+2k, the
# view's 8765+k, for the first k whose ports are free on this host (--lcm-url, --view-port choose them);
# two runs into one --out DIR refuse to run together.
# Outputs (default out/), in every mode: the map (map.ogfs, the daemon's snapshot; map.ogfm with --pcap),
# map_occupied.ply, map.bt (the map as an OctoMap tree), png/*.png, accuracy.txt, nav/ (map.pgm, map.yaml),
# logs/; the main job and --pcap also octomap.bt (OctoMap's map of the same rays), the simulated modes sim/
# (capture, odometry, truth). The last line is "outputs: DIR".
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$here/scripts/run-common.sh"
out=$here/out
speed=1
duration=20
world=lab
pcap=
url=          # default: udpm://239.255.76.67:7689?ttl=0, or the next free port (see pick_run_slot)
view_port=    # default: 8765, or the next free port
view_wait=0
rig=
robots=
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --speed) speed=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --world) world=$2; shift 2 ;;
    --pcap) pcap=$2; shift 2 ;;
    --lcm-url) url=$2; shift 2 ;;
    --view-port) view_port=$2; shift 2 ;;
    --view-wait) view_wait=$2; shift 2 ;;
    --rig) rig=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    -h|--help) sed -n '2,26p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

mkdir -p "$out/logs" "$out/png"
out=$(cd "$out" && pwd)
exec 9>"$out/.run.lock"
if ! flock -n 9; then echo "run.sh: another run.sh is writing $out; give this one its own --out DIR" >&2; exit 1; fi
bash "$here/scripts/install-deps.sh" --main
bash "$here/scripts/multicast-loopback.sh"
bash "$here/scripts/build.sh" --main
bin=${OGF_BUILD_DIR:-$here/build}/bin
# One run, one bus and one set of ports, free on this host: two runs side by side (or a run beside a live
# mapper) never hear each other.
slot=$(pick_run_slot) || { echo "run.sh: no free LCM/UDP/TCP port slot on this host" >&2; exit 1; }
url=${url:-"udpm://239.255.76.67:$((7689 + slot))?ttl=0"}
view_port=${view_port:-$((8765 + slot))}
data_port=$((12368 + 2 * slot))      # not 2368: a real sensor on this host keeps its port
position_port=$((18308 + 2 * slot))

if [ -n "$rig" ] || [ -n "$robots" ]; then
  exec bash "$here/scripts/run-sources.sh" ${rig:+--rig "$rig"} ${robots:+--robots "$robots"} --out "$out" \
    --speed "$speed" --duration "$duration" --world "$world" --lcm-url "$url" --data-port "$data_port"
fi

if [ -n "$pcap" ]; then exec bash "$here/scripts/run-pcap.sh" --pcap "$pcap" --out "$out"; fi

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

echo "== simulating world '$world' for $duration s into $out/sim"
rm -rf "$out/sim" "$out/state"
# The simulated robot lives now: its GPS time (NMEA, PPS locked) is the current time, as a live sensor's is,
# so the driver's device clock (top-of-hour counter + hour) agrees before and after the first NMEA sentence.
"$bin/ogf-sim" --world "$world" --duration "$duration" --out "$out/sim" --start-utime "$(( $(date +%s) * 1000000 ))" \
  2>&1 | tee "$out/logs/sim.log"

# The mapper must know where the sensor sits on the body: ogf-sim wrote it into sim.yaml.
extrinsic=$(sim_extrinsic "$out/sim")
printf 'map:\n  extrinsic: %s\n' "$extrinsic" > "$out/mapper.yaml"

echo "== starting ogf-mapper, ogf-driver and ogf-map-client on $url"
"$bin/ogf-mapper" --lcm-url "$url" --state-dir "$out/state" --config "$out/mapper.yaml" >"$out/logs/mapper.log" 2>&1 &
mapper=$!; pids+=("$mapper")
"$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port "$data_port" --position-port "$position_port" \
  >"$out/logs/driver.log" 2>&1 &
driver=$!; pids+=("$driver")
"$bin/ogf-map-client" --lcm-url "$url" --nav --progress >"$out/logs/map-client.log" 2>&1 &
client=$!; pids+=("$client")
"$bin/ogf-view" --lcm-url "$url" --port "$view_port" >"$out/logs/view.log" 2>&1 &
view=$!; pids+=("$view")
for _ in $(seq 1 50); do grep -q '^ogf-view: http' "$out/logs/view.log" && break; sleep 0.1; done
if view_url=$(grep -m1 -o 'http://[^ ]*' "$out/logs/view.log"); then
  echo "== watch the map grow in a browser: $view_url"
  sleep "$view_wait"
else
  echo "run.sh: ogf-view did not start (see $out/logs/view.log); going on without it" >&2
fi

echo "== replaying the capture and the odometry at ${speed}x"
"$bin/ogf-replay" --pcap "$out/sim/capture.pcap" --dest 127.0.0.1 --data-port "$data_port" \
  --position-port "$position_port" --speed "$speed" --odometry "$out/sim/odometry.csv" --lcm-url "$url" \
  --start-delay 1.5 | tee "$out/replay.txt"

echo "== stopping the driver (it publishes the scan in progress), waiting until the map client's sequence"
echo "   stops moving (the mapper has drained its queue), then stopping the client and the mapper"
sleep 0.5
kill -TERM "$driver"; driver_rc=0; wait "$driver" || driver_rc=$?
wait_for_quiet_client "$out/logs/map-client.log"
kill -TERM "$client"; client_rc=0; wait "$client" || client_rc=$?
kill -TERM "$view" 2>/dev/null || true; wait "$view" 2>/dev/null || true
kill -TERM "$mapper"; mapper_rc=0; wait "$mapper" || mapper_rc=$?
pids=()
echo "driver exit $driver_rc, mapper exit $mapper_rc, map client exit $client_rc"
tail -n 2 "$out/logs/map-client.log" | tee "$out/map-client.txt"
if [ ! -f "$out/state/snapshot.ogfs" ]; then echo "run.sh: the mapper left no snapshot in $out/state" >&2; exit 1; fi
cp "$out/state/snapshot.ogfs" "$out/map.ogfs"

echo "== scoring the map against the ground truth and an OctoMap of the same rays"
"$bin/ogf-eval" --map "$out/map.ogfs" --truth "$out/sim" --png "$out/png" --export-ply "$out/map_occupied.ply" \
  --write-octomap "$out/octomap.bt" --nav | tee "$out/accuracy.txt"
finish_run "$bin" "$out" "$out/map.ogfs"
echo "sim:        $out/sim/ (capture, odometry, ground truth); replay summary $out/replay.txt"
echo "browser:    $bin/ogf-view --map $out/map.ogfs   (then open http://127.0.0.1:$view_port/)"
echo "outputs:    $out"
