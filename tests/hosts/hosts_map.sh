#!/usr/bin/env bash
# Several hosts: three network namespaces stand for the lidar computer on the robot ("driver"), the mapping
# computer ("mapper") and a computer that follows the map ("client"), made by scripts/netns-hosts.sh. On
# driver, ogf-replay sends a simulated VLP-16 capture over UDP to ogf-driver and publishes the odometry; on
# mapper, ogf-mapper maps; on client, ogf-map-client follows the deltas. LCM is udpm with ttl=1, so scans,
# odometry, deltas and keyframe requests all cross the network between the hosts.
#   TOPOLOGY lan:   the three on one Ethernet segment (a Linux bridge).
#   TOPOLOGY vxlan: each host on its own subnet behind a router that forwards no multicast, joined by a
#                   VXLAN tunnel that carries LCM's multicast (what docs/multi-host.md advises across links
#                   LCM does not reach).
# Checked from an lcm-logger log taken on mapper: the mapper received every scan the driver published and
# mapped them all, and the client's rebuilt map has the mapper's checksum.
# With ROBOTS >= 2 there is one host per robot (robot1, robot2, ...), each replaying the same capture as its
# own lidar on its own channels (VELODYNE_SCAN_R<k>, POSE_R<k>), robot k's odometry 30 (k-1) m further along
# x; the mapper maps them as sources lidar<k> of robots r<k>, and ogf-map-query sources, run on the client
# host, must list each with every scan its driver published mapped and its sensor where its odometry put it.
# Usage: hosts_map.sh BIN_DIR [lan|vxlan] [ROBOTS]. Exits 77 (skip) with the reason when namespaces (or VXLAN) cannot
# be made (not root, no iproute2, no CAP_SYS_ADMIN in a container, no vxlan module). Namespaces, links and
# processes are removed on every path.
set -uo pipefail
bin=${1:?usage: hosts_map.sh BIN_DIR [lan|vxlan] [ROBOTS]}
topology=${2:-lan}
robots=${3:-1}
[[ $robots =~ ^[1-9]$ ]] || { echo "ROBOTS must be 1 to 9"; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
netns_hosts=$here/../../scripts/netns-hosts.sh
skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*"; for f in "$work"/*.log; do echo "--- $f"; tail -n 20 "$f"; done; exit 1; }

case $topology in
  lan) topo_flags=() ;;
  vxlan) topo_flags=(--routed --vxlan) ;;
  *) echo "unknown topology '$topology' (lan or vxlan)"; exit 2 ;;
esac
[ "$(id -u)" = 0 ] || skip "network namespaces need root"
command -v ip >/dev/null || skip "iproute2 (ip) is not installed"
command -v lcm-logger >/dev/null || skip "lcm-logger is not installed"
for p in ogf-sim ogf-replay ogf-driver ogf-mapper ogf-map-client ogf-bus-check ogf-map-query; do
  [ -x "$bin/$p" ] || skip "$bin/$p is not built"
done

name=o$(( $$ % 10000000 ))   # unique per run, at most 8 characters
work=$(mktemp -d /tmp/ogf-hosts-XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  sleep 0.3
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
  bash "$netns_hosts" down "$name"
  if [ -z "${OGF_HOSTS_KEEP:-}" ]; then rm -rf "$work"; else echo "kept $work"; fi
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# Whether this kernel lets us make a namespace (and a VXLAN link) at all: a skip, not a failure.
ip netns add "$name-probe" 2>"$work/netns.err" || skip "cannot create a network namespace: $(cat "$work/netns.err")"
if [ "$topology" = vxlan ] &&
   ! ip -n "$name-probe" link add vx0 type vxlan id 1 dstport 4789 local 127.0.0.1 2>"$work/vxlan.err"; then
  skip "cannot create a VXLAN link: $(cat "$work/vxlan.err")"
fi
ip netns del "$name-probe"
robot_hosts=(driver)
[ "$robots" -gt 1 ] && robot_hosts=($(seq -f 'robot%g' 1 "$robots"))
bash "$netns_hosts" up "$name" "${topo_flags[@]}" "${robot_hosts[@]}" mapper client >"$work/netns.log" 2>&1 ||
  fail "scripts/netns-hosts.sh up failed"
cat "$work/netns.log"
ns_a=$name-${robot_hosts[0]} ns_b=$name-mapper ns_c=$name-client
if [ "$topology" = vxlan ]; then
  # The hosts are on different subnets: unicast goes through the router, multicast only into the tunnel.
  ip netns exec "$ns_a" ip route get "10.77.$((robots + 1)).1" | grep -q "via 10.77.1.254" ||
    fail "driver does not reach mapper through the router"
  ip netns exec "$ns_a" ip route get 239.255.76.67 | grep -q "dev vx0" || fail "multicast does not route into the tunnel on driver"
else
  ip netns exec "$ns_a" ip route get 239.255.76.67 | grep -q "dev eth0" || fail "multicast does not route over eth0 on driver"
fi

url="udpm://239.255.76.67:7667?ttl=1&recv_buf_size=8388608"

# What a user checks first (docs/multi-host.md): ogf-bus-check publishes every message type on driver,
# lcm-logger on mapper records what arrives. Sets heard to how many probe messages mapper heard. (Long
# steps run in the background and are waited for, so that a signal stops the test at once.)
probe_heard() {
  local log=$work/probe-$1.lcmlog
  ip netns exec "$ns_b" lcm-logger --lcm-url="$url" --channel='PROBE_.*' "$log" >"$work/probe-logger.log" 2>&1 &
  local logger=$!
  pids+=("$logger")
  sleep 0.5
  ip netns exec "$ns_a" "$bin/ogf-bus-check" --lcm-url "$url" --channel-prefix PROBE_ --timeout 2 >"$work/probe-$1.log" 2>&1 &
  local check=$!
  pids+=("$check")
  wait "$check" || fail "ogf-bus-check on driver failed ($1)"
  sleep 0.5
  kill -INT "$logger"; wait "$logger"
  heard=$(python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from lcm_log_check import events; print(sum(1 for _ in events(sys.argv[2])))' \
    "$here/../../scripts" "$log" 2>/dev/null || echo 0)
}
if [ "$topology" = vxlan ]; then
  # Control: over the routed network itself (multicast routed out of eth0), nothing reaches mapper.
  ip -n "$ns_a" route replace 224.0.0.0/4 dev eth0 || fail "cannot move driver's multicast route"
  probe_heard routed
  [ "$heard" -eq 0 ] || fail "mapper heard $heard probe messages over the router: the control does not hold"
  echo "without the tunnel: mapper heard 0 messages of driver's ogf-bus-check"
  ip -n "$ns_a" route replace 224.0.0.0/4 dev vx0 || fail "cannot route driver's multicast back into the tunnel"
fi
probe_heard "$topology"
[ "$heard" -gt 0 ] || fail "mapper heard none of driver's ogf-bus-check messages"
echo "$topology: mapper heard $heard messages of driver's ogf-bus-check"
# (Background processes are started with `ip netns exec` itself, which execs them: $! is then their pid.)

"$bin/ogf-sim" --world lab --duration "${OGF_HOSTS_SECONDS:-3}" --out "$work/sim" \
  --start-utime "$(( $(date +%s) * 1000000 ))" --log-level warn >"$work/sim.log" 2>&1 || fail "ogf-sim failed"
extrinsic=$(sed -n 's/^sensor_to_body: {xyz: \(\[[^]]*\]\), quaternion_wxyz: \(\[[^]]*\]\)}.*/translation: \1, quaternion: \2/p' "$work/sim/sim.yaml")
[ -n "$extrinsic" ] || fail "no sensor_to_body in sim.yaml"
# Robot k: its channels' suffix (none for a single robot: the default channels and configuration) and
# its odometry, 30 (k-1) m further along x.
suffix() { [ "$robots" = 1 ] || echo "_R$1"; }
{
  printf 'status_interval_s: 0.2\nfusion:\n  max_pending_scans: 64\n  max_pending_points: 4000000\n'
  if [ "$robots" = 1 ]; then
    printf 'map:\n  extrinsic: {%s}\n' "$extrinsic"
  else
    echo "sources:"
    for k in $(seq 1 "$robots"); do
      printf '  - {name: lidar%d, robot: r%d, scan_channel: VELODYNE_SCAN_R%d, pose_channel: POSE_R%d, extrinsic: {%s}}\n' \
        "$k" "$k" "$k" "$k" "$extrinsic"
    done
  fi
} >"$work/mapper.yaml"
for k in $(seq 1 "$robots"); do
  awk -F, -v dx=$((30 * (k - 1))) 'BEGIN { OFS = "," } NR == 1 { print; next } { $2 = sprintf("%.6f", $2 + dx); print }' \
    "$work/sim/odometry.csv" >"$work/odometry-$k.csv"
done

ip netns exec "$ns_b" lcm-logger --lcm-url="$url" --channel='OGF_MAPPER_STATUS|VELODYNE_STATUS.*' "$work/bus.lcmlog" >"$work/logger.log" 2>&1 &
pids+=($!)
ip netns exec "$ns_b" "$bin/ogf-mapper" --lcm-url "$url" --in-memory --config "$work/mapper.yaml" --log-level warn >"$work/mapper.log" 2>&1 &
mapper=$!; pids+=("$mapper")
ip netns exec "$ns_c" "$bin/ogf-map-client" --lcm-url "$url" --duration 300 --log-level warn >"$work/client.log" 2>&1 &
client=$!; pids+=("$client")
drivers=() replays=()
for k in $(seq 1 "$robots"); do
  ip netns exec "$name-${robot_hosts[$((k - 1))]}" "$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 \
    --data-port 12368 --position-port 18308 --scan-channel "VELODYNE_SCAN$(suffix "$k")" \
    --status-channel "VELODYNE_STATUS$(suffix "$k")" --no-packets --log-level warn >"$work/driver-$k.log" 2>&1 &
  drivers+=($!); pids+=($!)
done
sleep 1
for k in $(seq 1 "$robots"); do
  ip netns exec "$name-${robot_hosts[$((k - 1))]}" "$bin/ogf-replay" --pcap "$work/sim/capture.pcap" --dest 127.0.0.1 \
    --data-port 12368 --position-port 18308 --odometry "$work/odometry-$k.csv" --pose-channel "POSE$(suffix "$k")" \
    --lcm-url "$url" --start-delay 1 >"$work/replay-$k.log" 2>&1 &
  replays+=($!); pids+=($!)
done
for p in "${replays[@]}"; do wait "$p" || fail "ogf-replay failed"; done
sleep 0.5
for p in "${drivers[@]}"; do kill -TERM "$p"; wait "$p" || fail "ogf-driver exited $?"; done

# Wait until the mapper has dealt with every scan the driver published (its status says so).
status() { python3 "$here/lcm_log_status.py" "$work/bus.lcmlog" 2>/dev/null | sed -n "s/^$1 //p"; }
published_total() {
  local k n total=0
  for k in $(seq 1 "$robots"); do
    n=$(status "driver$(suffix "$k").scans_published"); [ -n "$n" ] || return
    total=$((total + n))
  done
  echo "$total"
}
for _ in $(seq 1 60); do
  sleep 1
  published=$(published_total); in=$(status mapper.scans_in); mapped=$(status mapper.scans_mapped)
  [ -n "$published" ] && [ -n "$in" ] && [ "$in" -ge "$published" ] && [ "$mapped" -ge "$in" ] && break
done
# Several robots: what the mapper says of each, asked from the client's host.
if [ "$robots" -gt 1 ]; then
  ip netns exec "$ns_c" "$bin/ogf-map-query" --lcm-url "$url" --timeout 10 sources --json >"$work/sources.json" 2>"$work/sources.err" ||
    fail "ogf-map-query sources on client failed: $(cat "$work/sources.err")"
fi
sleep 1  # the last delta's way to the client
kill -TERM "$client"; wait "$client" || fail "ogf-map-client exited $?"
kill -TERM "$mapper"; wait "$mapper" || fail "ogf-mapper exited $?"
python3 "$here/lcm_log_status.py" "$work/bus.lcmlog" >"$work/status.txt" || fail "cannot read the bus log"
cat "$work/status.txt"
line=$(tail -n 1 "$work/client.log")
echo "client: $line"

published=$(published_total); in=$(status mapper.scans_in); mapped=$(status mapper.scans_mapped)
rejected=$(status mapper.scans_rejected)
[ -n "$published" ] || fail "no VELODYNE_STATUS crossed from driver to mapper"
[ -n "$in" ] || fail "no OGF_MAPPER_STATUS on mapper"
[ "$published" -gt 0 ] || fail "the driver published no scan"
[ "$in" -eq "$published" ] || fail "the mapper received $in of the $published scans published on driver"
[ "$mapped" -gt 0 ] && [ "$mapped" -eq "$in" ] || fail "the mapper mapped $mapped of $in scans"
[ "$rejected" -eq 0 ] || fail "the mapper rejected $rejected scans"
for r in $(seq 1 "$robots"); do
  for k in packets_lost bad_size bad_block_flag foreign_sender bad_other; do
    [ "$(status "driver$(suffix "$r").$k")" = 0 ] || fail "driver $r counted $k $(status "driver$(suffix "$r").$k")"
  done
done
for k in scans_dropped_behind scans_dropped_no_pose scans_late poses_rejected; do
  [ "$(status mapper.$k)" = 0 ] || fail "the mapper counted $k $(status mapper.$k)"
done
rows=$(grep -c '^[0-9]' "$work/sim/odometry.csv")
[ "$(status mapper.poses_in)" = $((rows * robots)) ] ||
  fail "the mapper received $(status mapper.poses_in) of the $((rows * robots)) odometry rows"
grep -q ' gaps 0 keyframes 1 ' <<<"$line" || fail "the client saw a gap or more than one keyframe: $line"
checksum=$(sed -n 's/.* published_checksum \([0-9a-f]*\) mapper_published_checksum.*/\1/p' <<<"$line")
server=$(sed -n 's/.* mapper_published_checksum \([0-9a-f]*\) .*/\1/p' <<<"$line")
[ -n "$checksum" ] && [ "$checksum" = "$server" ] ||
  fail "client published_checksum '$checksum' != mapper_published_checksum '$server'"
if [ "$robots" -gt 1 ]; then
  cat "$work/sources.json"
  python3 - "$work/sources.json" "$work/status.txt" "$robots" "$rows" <<'PY' || fail "ogf-map-query sources does not match"
import json, sys
sources = json.load(open(sys.argv[1]))["sources"]
status = dict(line.split() for line in open(sys.argv[2]))
robots, rows = int(sys.argv[3]), int(sys.argv[4])
assert len(sources) == robots, f"{len(sources)} sources listed, {robots} robots"
first_x = None
for k, s in enumerate(sorted(sources, key=lambda s: s["robot"]), start=1):
    published = int(status[f"driver_R{k}.scans_published"])
    assert (s["robot"], s["sensor"], s["channel"], s["pose_channel"]) == (f"r{k}", f"lidar{k}", f"VELODYNE_SCAN_R{k}", f"POSE_R{k}"), s
    assert s["scans_in"] == s["scans_mapped"] == published > 0, f"r{k}: {s['scans_mapped']} of {s['scans_in']} mapped, {published} published"
    assert s["scans_dropped"] == s["scans_rejected"] == 0 and s["poses_in"] == rows, s
    assert s["trail"], f"r{k} has no trail"
    x = s["trail"][-1][0]
    first_x = x if first_x is None else first_x
    assert abs(x - first_x - 30 * (k - 1)) < 1e-2, f"r{k}'s sensor at x {x}, r1's at {first_x}"
    print(f"r{k}/lidar{k}: {published} published on robot{k}, {s['scans_mapped']} mapped, last at x {x:.2f}")
PY
fi
echo "PASS ($topology, $robots robots): $published scans crossed from $ns_a to $ns_b, $mapped mapped, the client on $ns_c ends with the mapper's checksum $checksum"
