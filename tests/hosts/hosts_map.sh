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
# Usage: hosts_map.sh BIN_DIR [lan|vxlan]. Exits 77 (skip) with the reason when namespaces (or VXLAN) cannot
# be made (not root, no iproute2, no CAP_SYS_ADMIN in a container, no vxlan module). Namespaces, links and
# processes are removed on every path.
set -uo pipefail
bin=${1:?usage: hosts_map.sh BIN_DIR [lan|vxlan]}
topology=${2:-lan}
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
for p in ogf-sim ogf-replay ogf-driver ogf-mapper ogf-map-client ogf-bus-check; do
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
bash "$netns_hosts" up "$name" "${topo_flags[@]}" driver mapper client >"$work/netns.log" 2>&1 ||
  fail "scripts/netns-hosts.sh up failed"
cat "$work/netns.log"
ns_a=$name-driver ns_b=$name-mapper ns_c=$name-client
if [ "$topology" = vxlan ]; then
  # The hosts are on different subnets: unicast goes through the router, multicast only into the tunnel.
  ip netns exec "$ns_a" ip route get 10.77.2.1 | grep -q "via 10.77.1.254" || fail "driver does not reach mapper through the router"
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
printf 'status_interval_s: 0.2\nmap:\n  extrinsic: {%s}\nfusion:\n  max_pending_scans: 64\n  max_pending_points: 2000000\n' \
  "$extrinsic" >"$work/mapper.yaml"

ip netns exec "$ns_b" lcm-logger --lcm-url="$url" --channel='OGF_MAPPER_STATUS|VELODYNE_STATUS' "$work/bus.lcmlog" >"$work/logger.log" 2>&1 &
pids+=($!)
ip netns exec "$ns_b" "$bin/ogf-mapper" --lcm-url "$url" --in-memory --config "$work/mapper.yaml" --log-level warn >"$work/mapper.log" 2>&1 &
mapper=$!; pids+=("$mapper")
ip netns exec "$ns_c" "$bin/ogf-map-client" --lcm-url "$url" --duration 300 --log-level warn >"$work/client.log" 2>&1 &
client=$!; pids+=("$client")
ip netns exec "$ns_a" "$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port 12368 --position-port 18308 \
  --no-packets --log-level warn >"$work/driver.log" 2>&1 &
driver=$!; pids+=("$driver")
sleep 1
ip netns exec "$ns_a" "$bin/ogf-replay" --pcap "$work/sim/capture.pcap" --dest 127.0.0.1 --data-port 12368 --position-port 18308 \
  --odometry "$work/sim/odometry.csv" --lcm-url "$url" --start-delay 1 >"$work/replay.log" 2>&1 &
replay=$!; pids+=("$replay")
wait "$replay" || fail "ogf-replay failed"
sleep 0.5
kill -TERM "$driver"; wait "$driver" || fail "ogf-driver exited $?"

# Wait until the mapper has dealt with every scan the driver published (its status says so).
status() { python3 "$here/lcm_log_status.py" "$work/bus.lcmlog" 2>/dev/null | sed -n "s/^$1 //p"; }
for _ in $(seq 1 60); do
  sleep 1
  published=$(status driver.scans_published); in=$(status mapper.scans_in); mapped=$(status mapper.scans_mapped)
  [ -n "$published" ] && [ -n "$in" ] && [ "$in" -ge "$published" ] && [ "$mapped" -ge "$in" ] && break
done
sleep 1  # the last delta's way to the client
kill -TERM "$client"; wait "$client" || fail "ogf-map-client exited $?"
kill -TERM "$mapper"; wait "$mapper" || fail "ogf-mapper exited $?"
python3 "$here/lcm_log_status.py" "$work/bus.lcmlog" >"$work/status.txt" || fail "cannot read the bus log"
cat "$work/status.txt"
line=$(tail -n 1 "$work/client.log")
echo "client: $line"

published=$(status driver.scans_published); in=$(status mapper.scans_in); mapped=$(status mapper.scans_mapped)
rejected=$(status mapper.scans_rejected)
[ -n "$published" ] || fail "no VELODYNE_STATUS crossed from driver to mapper"
[ -n "$in" ] || fail "no OGF_MAPPER_STATUS on mapper"
[ "$published" -gt 0 ] || fail "the driver published no scan"
[ "$in" -eq "$published" ] || fail "the mapper received $in of the $published scans published on driver"
[ "$mapped" -gt 0 ] && [ "$mapped" -eq "$in" ] || fail "the mapper mapped $mapped of $in scans"
[ "$rejected" -eq 0 ] || fail "the mapper rejected $rejected scans"
for k in packets_lost bad_size bad_block_flag foreign_sender bad_other; do
  [ "$(status driver.$k)" = 0 ] || fail "the driver counted $k $(status driver.$k)"
done
for k in scans_dropped_behind scans_dropped_no_pose scans_late poses_rejected; do
  [ "$(status mapper.$k)" = 0 ] || fail "the mapper counted $k $(status mapper.$k)"
done
rows=$(grep -c '^[0-9]' "$work/sim/odometry.csv")
[ "$(status mapper.poses_in)" = "$rows" ] || fail "the mapper received $(status mapper.poses_in) of the $rows odometry rows"
grep -q ' gaps 0 keyframes 1 ' <<<"$line" || fail "the client saw a gap or more than one keyframe: $line"
checksum=$(sed -n 's/.* published_checksum \([0-9a-f]*\) mapper_published_checksum.*/\1/p' <<<"$line")
server=$(sed -n 's/.* mapper_published_checksum \([0-9a-f]*\) .*/\1/p' <<<"$line")
[ -n "$checksum" ] && [ "$checksum" = "$server" ] ||
  fail "client published_checksum '$checksum' != mapper_published_checksum '$server'"
echo "PASS ($topology): $published scans crossed from $ns_a to $ns_b, $mapped mapped, the client on $ns_c ends with the mapper's checksum $checksum"
