#!/usr/bin/env bash
# The main job on a real capture of a sensor standing still, as scripts/run.sh --pcap runs it (after
# installing and building): ogf-map --static maps it offline (fixed pose at the origin, the same ScanMapper
# as the daemon); there is no ground truth, so ogf-eval --pcap scores how the map and an OctoMap of the same
# returns hold those returns.
#   scripts/run-pcap.sh --pcap FILE [--calib FILE] [--out DIR]
# Outputs (default out/): those of every mode of run.sh (map.ogfm, map_occupied.ply, map.bt, png/, accuracy.txt,
# nav/, logs/; scripts/run-common.sh, finish_run) and octomap.bt. The last line is "outputs: DIR".
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$here/scripts/run-common.sh"
out=$here/out
pcap=
calib=()
while [ $# -gt 0 ]; do
  case "$1" in
    --pcap) pcap=$2; shift 2 ;;
    --calib) calib=(--calib "$2"); shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run-pcap.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [ -z "$pcap" ]; then echo "run-pcap.sh: --pcap FILE is required" >&2; exit 2; fi
if [ ! -f "$pcap" ]; then echo "run-pcap.sh: $pcap: no such file" >&2; exit 2; fi
bin=${OGF_BUILD_DIR:-$here/build}/bin
mkdir -p "$out/logs" "$out/png"
out=$(cd "$out" && pwd)

echo "== mapping $pcap (a sensor standing still) into $out/map.ogfm"
"$bin/ogf-map" --pcap "$pcap" ${calib[@]+"${calib[@]}"} --static --out "$out/map.ogfm" \
  --export-ply "$out/map_occupied.ply" --png "$out/png" 2>&1 | tee "$out/logs/map.log"
echo "== scoring the map and an OctoMap of the same returns on those returns (no ground truth)"
"$bin/ogf-eval" --pcap "$pcap" ${calib[@]+"${calib[@]}"} --static --write-octomap "$out/octomap.bt" \
  2>"$out/logs/eval.log" | tee "$out/accuracy.txt"
# The sensor's frame has its floor where the walls' band found it, not at z = 0: the grid's band starts there.
floor=$(grep -m1 -o 'floor at -\?[0-9.]* m' "$out/logs/map.log" | grep -o -- '-\?[0-9.]*' || true)
finish_run "$bin" "$out" "$out/map.ogfm" ${floor:+--nav-floor-z "$floor"}
echo "outputs:    $out"
