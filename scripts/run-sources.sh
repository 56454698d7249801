#!/usr/bin/env bash
# The main job with several sources, as scripts/run.sh --rig or --robots runs it (after installing and
# building): ogf-sim simulates the sensors of a rig on one robot, or several robots in one world; one
# ogf-driver per sensor decodes its capture on its own ports onto its own scan channel; one ogf-mapper maps
# every source into one map (its `sources:` list); one ogf-map-client per robot follows the map; one
# ogf-replay per capture plays them in step, each robot's odometry on its own channel. Then each sensor's
# (or robot's) map alone is made offline with ogf-map, and ogf-eval scores the shared map against the truth
# beside them: its coverage against their union's, its accuracy against the better one's.
#   scripts/run-sources.sh (--rig NAME|FILE | --robots N) [--out DIR] [--speed X] [--duration S]
#                          [--world PRESET|FILE] [--lcm-url URL] [--data-port P] [--hold-scans N]
# --hold-scans N: the mapper keeps up to N scans waiting (fusion.max_pending_scans, and 30 000 points each)
# where it would drop the oldest (default 10): a machine too busy to map at the sensor's rate then maps late
# instead of dropping scans.
# Sensor k's driver takes its data on port P + 2k (default 12368) and its position packets on P + 5940 + 2k.
# Outputs (default out/): those of every mode of run.sh (map.ogfs, map_occupied.ply, map.bt, png/,
# accuracy.txt, nav/, logs/; scripts/run-common.sh, finish_run), and alone/*.ogfm, mapper.yaml, sim/. The last
# line is "outputs: DIR".
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$here/scripts/run-common.sh"
out=$here/out
speed=1
duration=20
world=lab
rig=
robots=
url="udpm://239.255.76.67:7689?ttl=0"
data_port=12368
hold_scans=
while [ $# -gt 0 ]; do
  case "$1" in
    --rig) rig=$2; shift 2 ;;
    --robots) robots=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --speed) speed=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --world) world=$2; shift 2 ;;
    --lcm-url) url=$2; shift 2 ;;
    --data-port) data_port=$2; shift 2 ;;
    --hold-scans) hold_scans=$2; shift 2 ;;
    -h|--help) sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run-sources.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if { [ -z "$rig" ] && [ -z "$robots" ]; } || { [ -n "$rig" ] && [ -n "$robots" ]; }; then
  echo "run-sources.sh: give one of --rig NAME|FILE and --robots N" >&2; exit 2
fi
bin=${OGF_BUILD_DIR:-$here/build}/bin
mkdir -p "$out/logs"
out=$(cd "$out" && pwd)

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

echo "== simulating world '$world' for $duration s into $out/sim (${rig:+rig $rig}${robots:+$robots robots})"
rm -rf "$out/sim" "$out/state" "$out/alone"
"$bin/ogf-sim" --world "$world" --duration "$duration" --out "$out/sim" --start-utime "$(( $(date +%s) * 1000000 ))" \
  ${rig:+--rig "$rig"} ${robots:+--robots "$robots"} 2>&1 | tee "$out/logs/sim.log"

# Every folder of the run with a sim.yaml is one sensor's capture: a sensor of the rig (one robot, `robot`,
# on POSE) or a robot (its own odometry on POSE_<ROBOT>).
folders=()
for d in "$out"/sim/*/; do [ -f "$d/sim.yaml" ] && folders+=("$(basename "$d")"); done
if [ "${#folders[@]}" -lt 2 ]; then echo "run-sources.sh: ogf-sim wrote fewer than two sensors in $out/sim" >&2; exit 1; fi
upper() { echo "$1" | tr '[:lower:]-' '[:upper:]_'; }
{
  echo "sources:"
  for name in "${folders[@]}"; do
    if [ -n "$rig" ]; then robot=robot; pose=POSE; else robot=$name; pose=POSE_$(upper "$name"); fi
    echo "  - {name: $name, robot: $robot, scan_channel: VELODYNE_SCAN_$(upper "$name"), pose_channel: $pose,"
    echo "     extrinsic: $(sim_extrinsic "$out/sim/$name")}"
  done
  if [ -n "$hold_scans" ]; then
    printf 'fusion:\n  max_pending_scans: %s\n  max_pending_points: %s\n' "$hold_scans" "$((hold_scans * 30000))"
  fi
} > "$out/mapper.yaml"
echo "== the mapper's sources ($out/mapper.yaml)"; cat "$out/mapper.yaml"

echo "== starting ogf-mapper, one ogf-driver per sensor and one ogf-map-client per robot on $url"
"$bin/ogf-mapper" --lcm-url "$url" --state-dir "$out/state" --config "$out/mapper.yaml" >"$out/logs/mapper.log" 2>&1 &
mapper=$!; pids+=("$mapper")
drivers=(); clients=(); k=0
for name in "${folders[@]}"; do
  ch=$(upper "$name")
  "$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port $((data_port + 2 * k)) \
    --position-port $((data_port + 5940 + 2 * k)) --scan-channel "VELODYNE_SCAN_$ch" --packets-channel "VELODYNE_PACKETS_$ch" \
    --status-channel "VELODYNE_STATUS_$ch" >"$out/logs/driver-$name.log" 2>&1 &
  drivers+=($!); pids+=($!)
  k=$((k + 1))
done
nclients=1; [ -n "$robots" ] && nclients=${#folders[@]}
for c in $(seq 1 "$nclients"); do
  "$bin/ogf-map-client" --lcm-url "$url" --progress >"$out/logs/map-client-$c.log" 2>&1 &
  clients+=($!); pids+=($!)
done

echo "== replaying the ${#folders[@]} captures in step at ${speed}x"
replays=(); k=0
for name in "${folders[@]}"; do
  odometry=()
  if [ -n "$robots" ]; then
    odometry=(--odometry "$out/sim/$name/odometry.csv" --pose-channel "POSE_$(upper "$name")" --lcm-url "$url")
  elif [ "$k" -eq 0 ]; then
    odometry=(--odometry "$out/sim/$name/odometry.csv" --lcm-url "$url")  # one robot: its odometry once
  fi
  "$bin/ogf-replay" --pcap "$out/sim/$name/capture.pcap" --dest 127.0.0.1 --data-port $((data_port + 2 * k)) \
    --position-port $((data_port + 5940 + 2 * k)) --speed "$speed" ${odometry[@]+"${odometry[@]}"} \
    --start-delay 1.5 >"$out/logs/replay-$name.log" 2>&1 &
  replays+=($!); pids+=($!)
  k=$((k + 1))
done
for r in "${replays[@]}"; do wait "$r"; done

echo "== stopping the drivers, waiting until the map clients' sequence stops moving, stopping the rest"
sleep 0.5
for d in "${drivers[@]}"; do kill -TERM "$d"; wait "$d" || true; done
wait_for_quiet_client "$out/logs/map-client-1.log"
for c in "${clients[@]}"; do kill -TERM "$c"; wait "$c" || true; done
kill -TERM "$mapper"; mapper_rc=0; wait "$mapper" || mapper_rc=$?
pids=()
echo "mapper exit $mapper_rc; $(grep -o 'stopping: .*' "$out/logs/mapper.log" | tail -n 1)"
consistent=yes
for c in $(seq 1 "$nclients"); do
  line=$(tail -n 1 "$out/logs/map-client-$c.log")
  echo "map client $c: $line"
  case "$line" in *"consistent yes"*) ;; *) consistent=no ;; esac
done
if [ ! -f "$out/state/snapshot.ogfs" ]; then echo "run-sources.sh: the mapper left no snapshot in $out/state" >&2; exit 1; fi
cp "$out/state/snapshot.ogfs" "$out/map.ogfs"

echo "== each source's map alone (ogf-map, offline, the same captures and odometry)"
mkdir -p "$out/alone"
alone=()
for name in "${folders[@]}"; do
  printf 'map:\n  extrinsic: %s\n' "$(sim_extrinsic "$out/sim/$name")" > "$out/alone/$name.yaml"
  "$bin/ogf-map" --pcap "$out/sim/$name/capture.pcap" --odometry "$out/sim/$name/odometry.csv" \
    --config "$out/alone/$name.yaml" --out "$out/alone/$name.ogfm" >"$out/logs/alone-$name.log" 2>&1
  alone+=(--alone "$out/alone/$name.ogfm")
done

echo "== scoring the shared map against the ground truth, beside each source alone"
mkdir -p "$out/png"
"$bin/ogf-eval" --map "$out/map.ogfs" --truth "$out/sim/${folders[0]}" --no-octomap "${alone[@]}" \
  --png "$out/png" --export-ply "$out/map_occupied.ply" --log-level warn | tee "$out/accuracy.txt"
finish_run "$bin" "$out" "$out/map.ogfs"
echo "alone:      $out/alone/*.ogfm (each source's map alone)"
echo "sim:        $out/sim/ (each sensor's capture, odometry and ground truth)"
echo "map clients consistent with the mapper: $consistent"
echo "outputs:    $out"
[ "$consistent" = yes ] && [ "$mapper_rc" -eq 0 ]
