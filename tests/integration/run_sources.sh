#!/usr/bin/env bash
# scripts/run.sh --rig front-rear / --robots 2 as a user runs them, shortened: every process real, on udpm
# over loopback. Passes when every map client ends consistent with the mapper (run-sources.sh's exit
# status), it left the outputs of every mode (run_outputs.sh), the mapper mapped every scan of every sensor
# (none dropped: it may hold all 120 scans of the 6 s run waiting, --hold-scans, so a busy machine makes it
# late, not lossy), and the shared map covers at least the
# union of what each source maps alone (the cells one classifies and none contradicts) and is at least as accurate as the better of them (ogf-eval --alone).
#   tests/integration/run_sources.sh BIN_DIR rig|robots
set -euo pipefail
bin=$1
mode=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out=$(mktemp -d /tmp/ogf-run-sources-XXXXXX)
slot=$(( $$ % 400 ))
args=(--rig front-rear); [ "$mode" = robots ] && args=(--robots 2)
if ! OGF_BUILD_DIR=$(dirname "$bin") bash "$here/scripts/run-sources.sh" "${args[@]}" --out "$out" --duration 6 --hold-scans 150 \
     --lcm-url "udpm://239.255.76.67:$((20000 + slot))?ttl=0&recv_buf_size=8388608" --data-port $((30000 + 20 * slot)) \
     > "$out/run.txt" 2>&1; then
  cat "$out/run.txt"; echo "FAIL: run-sources.sh $mode failed (output above, files in $out)"; exit 1
fi
fail() { cat "$out/run.txt"; echo "FAIL: $*"; exit 1; }
source "$here/tests/integration/run_outputs.sh"
check_run_outputs "$out" "$out/run.txt" map.ogfs || fail "the outputs of every mode (above)"
[ -s "$out/png/truth.png" ] && [ -s "$out/png/ogf_errors.png" ] || fail "no truth.png or ogf_errors.png in $out/png"
stopping=$(grep -o 'stopping: .*' "$out/logs/mapper.log" | tail -n 1)
echo "mapper: $stopping"
case "$stopping" in *" 0 dropped behind, 0 without poses"*) ;; *) fail "the mapper did not map every scan: $stopping" ;; esac
read -r cov union < <(sed -n 's/^  coverage: \([0-9.]*\), the union of the sources alone \([0-9.]*\) .*/\1 \2/p' "$out/accuracy.txt")
read -r acc better < <(sed -n 's/^  accuracy: \([0-9.]*\), the better source alone \([0-9.]*\)$/\1 \2/p' "$out/accuracy.txt")
[ -n "$cov" ] && [ -n "$acc" ] || fail "no comparison with the sources alone in accuracy.txt"
echo "coverage $cov (union of the sources alone $union), accuracy $acc (better source alone $better)"
awk -v a="$cov" -v b="$union" 'BEGIN { exit !(a >= b) }' || fail "coverage $cov below the union's $union"
awk -v a="$acc" -v b="$better" 'BEGIN { exit !(a >= b) }' || fail "accuracy $acc below the better source's $better"
rm -rf "$out"
echo "PASS: run.sh ${args[*]}"
