#!/usr/bin/env bash
# The map-quality figures of the README: the OGF against OctoMap (Debian's liboctomap, same rays, same
# resolution) on the simulated worlds and on a real static capture, and what each occupied-priority policy
# leaves behind of a person walking through the lab.
#   scripts/accuracy.sh [--out DIR] [--quick]
#     --quick: the lab only, 10 s, no held-out test (about a minute)
# Needs a build (scripts/build.sh); reads the real capture from ../shared/data/real when it is there.
# Writes every ogf-eval table to DIR (default out/accuracy) and prints a summary table.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$here/out/accuracy
quick=0
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    -h|--help) sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "accuracy.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
bin=${OGF_BUILD_DIR:-$here/build}/bin
for p in ogf-sim ogf-eval; do
  [ -x "$bin/$p" ] || { echo "accuracy.sh: $bin/$p missing: run scripts/build.sh first" >&2; exit 1; }
done
mkdir -p "$out"
out=$(cd "$out" && pwd)
shared=${OGF_SHARED_DIR:-$here/../shared}

# value TABLE ROW COLUMN: the COLUMN-th figure (1 OGF, 2 OctoMap: the last two) of the first row starting with ROW.
value() { awk -v row="$2" -v col="$3" 'index($0, row) == 1 { print $(NF - 2 + col); exit }' "$1"; }

if [ "$quick" = 1 ]; then worlds="lab:10"; held=(); else worlds="lab:20 warehouse:15 street:14"; held=(--held-out); fi

echo "== simulated worlds (true poses, 0.2 m): OGF | OctoMap"
printf '%-10s %-17s %-17s %-17s %-17s %-17s %-13s %-17s %-17s\n' world accuracy "occ. recall" "occ. precision" \
  "ROC AUC" "gaps filled" "filled wrongly" "held-out AUC" "unseen-cell AUC"
for w in $worlds; do
  name=${w%%:*}
  secs=${w##*:}
  "$bin/ogf-sim" --world "$name" --duration "$secs" --out "$out/sim-$name" --log-level warn > /dev/null
  "$bin/ogf-eval" --truth "$out/sim-$name" "${held[@]}" --log-level warn > "$out/$name.txt"
  t=$out/$name.txt
  pair() { printf '%s | %s' "$(value "$t" "$1" 1)" "$(value "$t" "$1" 2)"; }
  printf '%-10s %-17s %-17s %-17s %-17s %-17s %-13s %-17s %-17s\n' "$name" "$(pair 'accuracy (eq. 13')" \
    "$(pair 'recall (occupied)')" "$(pair 'precision (occupied)')" "$(pair 'ROC AUC (probability)')" \
    "$(pair 'gap filling (share)')" "$(pair 'filled wrongly')" "$(pair 'held-out ROC AUC')" \
    "$(pair 'unseen cells: ROC AUC')"
done

echo
echo "== a person walking through the lab (ogf-sim --movers person): swept free cells left occupied"
"$bin/ogf-sim" --world lab --movers person --duration 16 --out "$out/sim-lab-person" --log-level warn > /dev/null
for policy in "scan:0" "map:20" "map:0"; do
  printf 'filter:\n  occupied_priority: %s\n  free_release_scans: %s\n' "${policy%%:*}" "${policy##*:}" \
    > "$out/policy.yaml"
  "$bin/ogf-eval" --truth "$out/sim-lab-person" --config "$out/policy.yaml" --log-level warn > "$out/person-${policy/:/-}.txt"
  t=$out/person-${policy/:/-}.txt
  printf '%-28s OGF %5s   OctoMap %5s   (of %s swept cells)\n' "occupied_priority ${policy%%:*}, release ${policy##*:}" \
    "$(value "$t" '... left occupied' 1)" "$(value "$t" '... left occupied' 2)" "$(value "$t" 'moving solid: swept free cells' 1)"
done

pcap=$shared/data/real/vlp-16-test-90deg-1-50-frames.pcap
calib=$shared/data/real/calib/VLP-16.xml
echo
if [ ! -f "$pcap" ]; then
  echo "== real static capture: skipped ($pcap absent)"
  exit 0
fi
echo "== real static capture $(basename "$pcap"): returns in occupied cells OGF | OctoMap; half-way points free OGF | OctoMap"
resolutions="0.05 0.1 0.2"
[ "$quick" = 1 ] && resolutions="0.2"
for r in $resolutions; do
  t=$out/real-$r.txt
  "$bin/ogf-eval" --pcap "$pcap" --static --calib "$calib" --resolution "$r" "${held[@]}" --log-level warn > "$t"
  printf '%-6s m  %s | %s   %s | %s' "$r" "$(value "$t" 'return cells classed occupied' 1)" \
    "$(value "$t" 'return cells classed occupied' 2)" "$(value "$t" 'half-way points classed free' 1)" \
    "$(value "$t" 'half-way points classed free' 2)"
  if [ "$quick" = 0 ]; then
    printf '   held-out AUC %s | %s' "$(value "$t" 'held-out ROC AUC' 1)" "$(value "$t" 'held-out ROC AUC' 2)"
  fi
  printf '\n'
done
