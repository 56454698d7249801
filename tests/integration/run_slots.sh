#!/usr/bin/env bash
# Two runs of scripts/run.sh on one host: each takes a bus and ports no process holds (pick_run_slot of
# scripts/run-common.sh), and a second run into the same --out DIR refuses to start beside the first.
#   tests/integration/run_slots.sh
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$here/scripts/run-common.sh"
fail() { echo "FAIL: $*"; exit 1; }
first=$(pick_run_slot) || fail "no free slot at all"
# A run holds the first slot's LCM port (as its mapper's udpm socket does) and its view's TCP port.
python3 - "$((7689 + first))" "$((8765 + first))" <<'PY' &
import socket, sys, time
u = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); u.bind(("0.0.0.0", int(sys.argv[1])))
t = socket.socket(socket.AF_INET, socket.SOCK_STREAM); t.bind(("127.0.0.1", int(sys.argv[2]))); t.listen()
print("bound", flush=True)
time.sleep(60)
PY
holder=$!
trap 'kill $holder 2>/dev/null || true' EXIT
for _ in $(seq 1 50); do port_free udp $((7689 + first)) || break; sleep 0.1; done
port_free udp $((7689 + first)) && fail "the holder did not bind port $((7689 + first))"
second=$(pick_run_slot) || fail "no second slot"
[ "$second" != "$first" ] || fail "the second run got slot $first, whose ports the first holds"
echo "first run slot $first, second run slot $second"
# The same --out DIR: the second run is refused while the first holds it.
out=$(mktemp -d /tmp/ogf-run-slots-XXXXXX)
exec 8>"$out/.run.lock"; flock -n 8 || fail "cannot take the lock"
msg=$(bash "$here/scripts/run.sh" --out "$out" 2>&1 </dev/null | tail -n 1 || true)
case "$msg" in *"another run.sh is writing $out"*) ;; *) fail "a second run into $out said: $msg" ;; esac
rm -rf "$out"
echo "PASS: runs side by side take their own ports, and one --out DIR at a time"
