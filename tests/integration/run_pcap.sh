#!/usr/bin/env bash
# scripts/run.sh --pcap as a user runs it on the real VLP-16 capture (what run.sh runs after installing and
# building: scripts/run-pcap.sh): passes when it leaves the outputs of every mode (run_outputs.sh), an
# accuracy.txt with the OGF's and OctoMap's scores on the capture's returns, and OctoMap's own map.
#   tests/integration/run_pcap.sh BIN_DIR SHARED_DIR
set -euo pipefail
bin=$1
shared=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
pcap=$shared/data/real/vlp-16-test-90deg-1-50-frames.pcap
if [ ! -f "$pcap" ]; then echo "SKIP: $pcap absent (the test reads ../shared)"; exit 0; fi
out=$(mktemp -d /tmp/ogf-run-pcap-XXXXXX)
if ! OGF_BUILD_DIR=$(dirname "$bin") bash "$here/scripts/run-pcap.sh" --pcap "$pcap" \
     --calib "$shared/data/real/calib/VLP-16.xml" --out "$out" > "$out/run.txt" 2>&1; then
  cat "$out/run.txt"; echo "FAIL: run-pcap.sh failed (output above, files in $out)"; exit 1
fi
fail() { cat "$out/run.txt"; echo "FAIL: $*"; exit 1; }
source "$here/tests/integration/run_outputs.sh"
check_run_outputs "$out" "$out/run.txt" map.ogfm || fail "the outputs of every mode (above)"
head -n 1 "$out/octomap.bt" | grep -q '^# Octomap OcTree binary file' || fail "octomap.bt is not an OctoMap .bt"
grep -q 'OctoMap' "$out/accuracy.txt" && grep -q 'OGF' "$out/accuracy.txt" ||
  fail "accuracy.txt does not score both maps: $(cat "$out/accuracy.txt")"
rm -rf "$out"
echo "PASS: run.sh --pcap"
