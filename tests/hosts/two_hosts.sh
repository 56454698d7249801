#!/usr/bin/env bash
# Several hosts: two network namespaces joined by a veth pair stand for the lidar computer and the mapping
# computer. In namespace A, ogf-replay sends a simulated VLP-16 capture over UDP to ogf-driver and publishes
# the odometry; in namespace B, ogf-mapper maps and ogf-map-client follows the deltas. LCM is udpm with
# ttl=1 over the veth (multicast route 224.0.0.0/4 on it), so scans and odometry must cross the link.
# Checked from an lcm-logger log taken in B: the mapper received every scan the driver published and
# mapped them (scans_mapped > 0), and the client's rebuilt map has the mapper's checksum.
# Usage: two_hosts.sh BIN_DIR. Exits 77 (skip) with the reason when namespaces cannot be made (not root,
# no iproute2, no CAP_SYS_ADMIN in a container). Namespaces, links and processes are removed on every path.
set -uo pipefail
bin=${1:?usage: two_hosts.sh BIN_DIR}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*"; for f in "$work"/*.log; do echo "--- $f"; tail -n 20 "$f"; done; exit 1; }

[ "$(id -u)" = 0 ] || skip "network namespaces need root"
command -v ip >/dev/null || skip "iproute2 (ip) is not installed"
command -v lcm-logger >/dev/null || skip "lcm-logger is not installed"
for p in ogf-sim ogf-replay ogf-driver ogf-mapper ogf-map-client; do
  [ -x "$bin/$p" ] || skip "$bin/$p is not built"
done

tag=$$
ns_a=ogf-a-$tag ns_b=ogf-b-$tag
veth_a=ogfa$tag veth_b=ogfb$tag   # at most 15 characters
work=$(mktemp -d /tmp/ogf-hosts-XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  sleep 0.3
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; done
  ip netns del "$ns_a" 2>/dev/null
  ip netns del "$ns_b" 2>/dev/null   # deleting a namespace deletes its end of the veth, and so the pair
  if [ -z "${OGF_HOSTS_KEEP:-}" ]; then rm -rf "$work"; else echo "kept $work"; fi
}
trap cleanup EXIT
trap 'exit 1' INT TERM

ip netns add "$ns_a" 2>"$work/netns.err" || skip "cannot create a network namespace: $(cat "$work/netns.err")"
ip netns add "$ns_b" || skip "cannot create a second network namespace"
ip link add "$veth_a" type veth peer name "$veth_b" 2>"$work/veth.err" || skip "cannot create a veth pair: $(cat "$work/veth.err")"
ip link set "$veth_a" netns "$ns_a" && ip link set "$veth_b" netns "$ns_b" || fail "cannot move the veth ends"
setup() {  # namespace, interface, address
  ip -n "$1" link set lo up &&
    ip -n "$1" addr add "$3/24" dev "$2" &&
    ip -n "$1" link set "$2" up multicast on &&
    ip -n "$1" route add 224.0.0.0/4 dev "$2"
}
setup "$ns_a" "$veth_a" 10.201.0.1 || fail "cannot configure $ns_a"
setup "$ns_b" "$veth_b" 10.201.0.2 || fail "cannot configure $ns_b"
ip netns exec "$ns_a" ip route get 239.255.76.67 | grep -q "dev $veth_a" || fail "multicast does not route over the veth in A"
echo "namespaces $ns_a ($veth_a 10.201.0.1) and $ns_b ($veth_b 10.201.0.2), multicast routed over the veth"

url="udpm://239.255.76.67:7667?ttl=1&recv_buf_size=8388608"
# (Background processes are started with `ip netns exec` itself, which execs them: $! is then their pid.)
in_a() { ip netns exec "$ns_a" "$@"; }
in_b() { ip netns exec "$ns_b" "$@"; }
# Raise the receive buffer limit in B (net.core is per namespace) for the 8 MiB LCM asks for.
in_b sysctl -qw net.core.rmem_max=16777216 2>/dev/null || true
in_a sysctl -qw net.core.rmem_max=16777216 2>/dev/null || true

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
ip netns exec "$ns_b" "$bin/ogf-map-client" --lcm-url "$url" --duration 300 --log-level warn >"$work/client.log" 2>&1 &
client=$!; pids+=("$client")
ip netns exec "$ns_a" "$bin/ogf-driver" --lcm-url "$url" --bind-address 127.0.0.1 --data-port 12368 --position-port 18308 \
  --no-packets --log-level warn >"$work/driver.log" 2>&1 &
driver=$!; pids+=("$driver")
sleep 1
in_a "$bin/ogf-replay" --pcap "$work/sim/capture.pcap" --dest 127.0.0.1 --data-port 12368 --position-port 18308 \
  --odometry "$work/sim/odometry.csv" --lcm-url "$url" --start-delay 1 >"$work/replay.log" 2>&1 || fail "ogf-replay failed"
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
[ -n "$published" ] || fail "no VELODYNE_STATUS crossed from A to B"
[ -n "$in" ] || fail "no OGF_MAPPER_STATUS in B"
[ "$published" -gt 0 ] || fail "the driver in A published no scan"
[ "$in" -eq "$published" ] || fail "the mapper in B received $in of the $published scans published in A"
[ "$mapped" -gt 0 ] && [ "$mapped" -eq "$in" ] || fail "the mapper mapped $mapped of $in scans"
[ "$rejected" -eq 0 ] || fail "the mapper rejected $rejected scans"
checksum=$(sed -n 's/.* published_checksum \([0-9a-f]*\) mapper_published_checksum.*/\1/p' <<<"$line")
server=$(sed -n 's/.* mapper_published_checksum \([0-9a-f]*\) .*/\1/p' <<<"$line")
[ -n "$checksum" ] && [ "$checksum" = "$server" ] ||
  fail "client published_checksum '$checksum' != mapper_published_checksum '$server'"
echo "PASS: $published scans crossed the veth from $ns_a to $ns_b, $mapped mapped, client checksum $checksum = mapper's"
