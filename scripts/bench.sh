#!/usr/bin/env bash
# Runs ogf's benchmark programs on built-in data and prints, for the machine it ran on, one performance
# table (every anchor, OctoMap first, measured in the same run); scripts/accuracy.sh prints the map-quality
# table. Needs a build with benchmarks (scripts/build.sh builds them); it builds nothing itself.
#   scripts/bench.sh [--quick] [--build-dir DIR] [--keep DIR]
#     --quick      short runs (a few scans, short repetitions): under a minute; the figures
#                  are noisier than a full run's, which takes a few minutes
#     --build-dir  the build tree (default $OGF_BUILD_DIR, else build/)
#     --keep DIR   keep every program's raw output in DIR (default: a temporary folder, removed)
# Programs: ogf-bench-octomap (street scans, and the real static capture, through the OGF and through
# OctoMap, and through Bonxai when it was built with -DOGF_BONXAI_DIR), ogf-bench-filter, ogf-bench-fusion and
# ogf-bench-driver_decoding (Google Benchmark).
# The capture rows and the decoding benchmark read the real captures in ../shared/data/real; without them
# their rows say so.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${OGF_BUILD_DIR:-$here/build}
quick=0
keep=
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1; shift ;;
    --build-dir) build=$2; shift 2 ;;
    --keep) keep=$2; shift 2 ;;
    -h|--help) sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
bin=$build/bin
for p in ogf-bench-octomap ogf-bench-filter ogf-bench-fusion ogf-bench-driver_decoding ogf-sim ogf-map ogf-eval; do
  if [ ! -x "$bin/$p" ]; then
    echo "bench.sh: $bin/$p not found; build first (scripts/build.sh, benchmarks are on by default)" >&2
    exit 1
  fi
done
if [ -n "$keep" ]; then mkdir -p "$keep"; work=$(cd "$keep" && pwd); else
  work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi

if [ "$quick" = 1 ]; then
  scans=4; resolutions=0.2; gb=(--benchmark_min_time=0.2); mode="quick (--quick)"
else
  scans=20; resolutions=0.2,0.1; gb=(--benchmark_repetitions=3 --benchmark_report_aggregates_only=true)
  mode="full"
fi
start=$(date +%s)

# One value of a Google Benchmark CSV: the row whose name is $2 (a median row in a full run), column $3.
gbval() {
  local file=$1 name=$2 col=$3
  [ "$quick" = 1 ] || name="${name}_median"
  # The name is quoted and may hold commas (capture(0=vlp16,1=dual,...)); the other fields do not.
  awk -v name="$name" -v col="$col" '
    /^name,/ { n = split($0, f, ","); for (i = 1; i <= n; i++) { gsub(/"/, "", f[i]); h[f[i]] = i }; next }
    /^"/ {
      e = index(substr($0, 2), "\"")
      if (substr($0, 2, e - 1) != name || !(col in h)) next
      split(substr($0, e + 3), f, ","); print f[h[col] - 1]; exit
    }' "$file"
}
# The Bonxai row beside OctoMap's, when ogf-bench-octomap was built with it: file, resolution, OGF ms, OGF MB.
bonxai_rows() {
  local bm bmem
  bm=$(octo "$1" "$2" Bonxai 3); bmem=$(octo "$1" "$2" Bonxai 7)
  [ -n "$bm" ] || return 0
  echo "| same: Bonxai (ProbabilisticMap), ms per scan / memory MB | $3 / $4 | Bonxai $bm / $bmem | OGF $(ratio "$bm" "$3")× faster, $(ratio "$4" "$bmem")× the memory |"
}
fmt() { awk -v v="$1" -v f="$2" 'BEGIN { if (v == "") print "n/a"; else printf(f, v) }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "" || b + 0 == 0) print "n/a"; else printf("%.2f", a / b) }'; }

echo "ogf benchmarks, $mode run; raw output in $work" >&2

echo "== ogf-bench-octomap --scans $scans --resolutions $resolutions" >&2
"$bin/ogf-bench-octomap" --scans "$scans" --resolutions "$resolutions" >"$work/octomap.txt"
static_capture=$here/../shared/data/real/vlp-16-test-90deg-1-50-frames.pcap
if [ -f "$static_capture" ]; then
  capture_res=0.2; [ "$quick" = 0 ] && capture_res=0.2,0.1,0.05
  echo "== ogf-bench-octomap --pcap $(basename "$static_capture") --scans 52 --resolutions $capture_res" >&2
  "$bin/ogf-bench-octomap" --pcap "$static_capture" --scans 52 --resolutions "$capture_res" >"$work/capture.txt"
fi
if [ "$quick" = 0 ]; then
  echo "== ogf-bench-octomap --scans $scans --resolutions 0.2 --deltas" >&2
  "$bin/ogf-bench-octomap" --scans "$scans" --resolutions 0.2 --deltas >"$work/octomap_deltas.txt"
  echo "== ogf-bench-octomap --scans $scans --resolutions 0.1 --no-octomap --threads 2" >&2
  "$bin/ogf-bench-octomap" --scans "$scans" --resolutions 0.1 --no-octomap --threads 2 >"$work/octomap_threads.txt"
fi
# Columns of a row: res, mapper, mean ms, p50 ms, p99 ms, x 10 Hz, memory MB, cells.
octo() { awk -v r="$2" -v m="$3" -v c="$4" '$1 == r && $2 == m { print $c; exit }' "$1"; }

echo "== ogf-bench-filter (default stencil)" >&2
"$bin/ogf-bench-filter" --benchmark_filter='Measurement/R2:(0|-1)/' --benchmark_format=csv "${gb[@]}" \
  >"$work/filter.csv" 2>"$work/filter.err"
echo "== ogf-bench-fusion" >&2
# One run per benchmark family: Google Benchmark's CSV reporter aborts when a later benchmark has a counter
# the first one did not have.
"$bin/ogf-bench-fusion" --benchmark_filter='^BM_CastRandomRays/' --benchmark_format=csv "${gb[@]}" \
  >"$work/fusion_rays.csv" 2>"$work/fusion_rays.err"
"$bin/ogf-bench-fusion" --benchmark_filter='^BM_MeasurementSetVlp16/' --benchmark_format=csv "${gb[@]}" \
  >"$work/fusion.csv" 2>"$work/fusion.err"
echo "== ogf-bench-driver_decoding" >&2
"$bin/ogf-bench-driver_decoding" --benchmark_format=csv "${gb[@]}" >"$work/decoding.csv" 2>"$work/decoding.err" || true


# ---------------------------------------------------------------------------------------------------------
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)
# The commit the programs were built from (the build tree's source folder), and whether it had changes.
src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
commit=$(git -C "${src:-$here}" rev-parse --short HEAD 2>/dev/null || echo unknown)
if ! git -C "${src:-$here}" diff --quiet HEAD -- 2>/dev/null; then commit="$commit with uncommitted changes"; fi
buildtype=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
echo
echo "Machine: $(nproc) CPUs, ${cpu:-unknown CPU}; $(uname -sr); load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "Code: $commit, build ${buildtype:-unknown}; scripts/bench.sh${quick:+ }$( [ "$quick" = 1 ] && echo --quick ); $(( $(date +%s) - start )) s"
echo

o=$work/octomap.txt
echo "| benchmark | ogf | anchor, same run | ratio |"
echo "|---|---|---|---|"
for r in $(tr ',' ' ' <<<"$resolutions"); do
  res=$(printf '%.2f' "$r")
  om=$(octo "$o" "$res" OGF 3); op99=$(octo "$o" "$res" OGF 5); orf=$(octo "$o" "$res" OGF 6); omem=$(octo "$o" "$res" OGF 7)
  cm=$(octo "$o" "$res" OctoMap 3); cp99=$(octo "$o" "$res" OctoMap 5); crf=$(octo "$o" "$res" OctoMap 6); cmem=$(octo "$o" "$res" OctoMap 7)
  echo "| street VLP-16 scans, $r m cells, 30 m: ms per scan, mean / p99 ($scans scans, 1 thread) | $om / $op99 | OctoMap $cm / $cp99 | OGF $(ratio "$cm" "$om")× faster |"
  echo "| same: × real time (10 Hz) | $orf | OctoMap $crf | |"
  echo "| same: memory, MB | $omem | OctoMap $cmem | $(ratio "$omem" "$cmem")× OctoMap's |"
  bonxai_rows "$o" "$res" "$om" "$omem"
done
c=$work/capture.txt
if [ -f "$c" ]; then
  for res in $(awk '$2 == "OGF" { print $1 }' "$c"); do
    om=$(octo "$c" "$res" OGF 3); omem=$(octo "$c" "$res" OGF 7)
    cm=$(octo "$c" "$res" OctoMap 3); cmem=$(octo "$c" "$res" OctoMap 7)
    echo "| real static capture (52 VLP-16 scans), $res m cells, 30 m: ms per scan / memory MB | $om / $omem | OctoMap $cm / $cmem | OGF $(ratio "$cm" "$om")× faster, $(ratio "$omem" "$cmem")× the memory |"
    bonxai_rows "$c" "$res" "$om" "$omem"
  done
else
  echo "| real static capture | skipped (no ../shared/data/real captures) | | |"
fi
if [ "$quick" = 0 ]; then
  dm=$(octo "$work/octomap_deltas.txt" 0.20 OGF 3); drf=$(octo "$work/octomap_deltas.txt" 0.20 OGF 6)
  cm=$(octo "$o" 0.20 OctoMap 3)
  echo "| same at 0.2 m with the delta stream's change detection (--deltas): ms per scan / × real time | $dm / $drf | OctoMap $cm | OGF $(ratio "$cm" "$dm")× faster |"
  # "published map: ...; N cells published per scan, delta stream X ms per scan (mean; ...)"
  dpub=$(sed -n 's/.* \([0-9]*\) cells published per scan.*/\1/p' "$work/octomap_deltas.txt" | head -1)
  dstream=$(sed -n 's/.*delta stream \([0-9.]*\) ms per scan.*/\1/p' "$work/octomap_deltas.txt" | head -1)
  echo "| same: the delta stream beside it (the published map and the messages, as ogf-mapper keeps them): ms per scan / cells published per scan | $dstream / $dpub | scan period 100 ms | |"
  tm=$(octo "$work/octomap_threads.txt" 0.10 OGF 3); tp50=$(octo "$work/octomap_threads.txt" 0.10 OGF 4)
  om=$(octo "$o" 0.10 OGF 3); op50=$(octo "$o" 0.10 OGF 4)
  echo "| street scans at 0.1 m on 2 filter threads (wall time): ms per scan, mean / p50 | $tm / $tp50 | 1 thread $om / $op50 | $(ratio "$om" "$tm")× / $(ratio "$op50" "$tp50")× one thread's speed |"
fi
f=$work/filter.csv
for y in -1 1; do
  kind=free; [ "$y" = 1 ] && kind=occupied
  upd=$(gbval "$f" "BM_AllocatedMeasurement/R2:-1/y:$y/threads:1" ns_per_measurement)
  updb=$(gbval "$f" "BM_AllocatedMeasurement/R2:0/y:$y/threads:1" ns_per_measurement)
  first=$(gbval "$f" "BM_FirstMeasurement/R2:-1/y:$y/threads:1" ns_per_measurement)
  upd2=$(gbval "$f" "BM_AllocatedMeasurement/R2:-1/y:$y/threads:2/real_time" ns_per_measurement)
  echo "| filter update alone, default stencil, $kind: ns per measurement, 1 thread / 2 threads | $(fmt "$upd" %.0f) / $(fmt "$upd2" %.0f) | banded storage $(fmt "$updb" %.0f) | $(ratio "$upd" "$updb") of banded's time |"
  echo "| filter first measurement (with block allocation), $kind: ns, 1 thread | $(fmt "$first" %.0f) | update alone $(fmt "$upd" %.0f) | $(ratio "$first" "$upd")× |"
done
echo "| filter memory per allocated cell, bytes | $(fmt "$(gbval "$f" "BM_FirstMeasurement/R2:-1/y:-1/threads:1" bytes_per_cell)" %.1f) | banded storage $(fmt "$(gbval "$f" "BM_FirstMeasurement/R2:0/y:-1/threads:1" bytes_per_cell)" %.1f) | |"
u=$work/fusion.csv
room=$(gbval "$u" "BM_MeasurementSetVlp16/street:0/resolution_mm:200" cpu_time)
street=$(gbval "$u" "BM_MeasurementSetVlp16/street:1/resolution_mm:200" cpu_time)
rays=$(gbval "$work/fusion_rays.csv" "BM_CastRandomRays/resolution_mm:200" cells/s)
echo "| measurement set of a VLP-16 scan at 0.2 m, room / street: ms | $(fmt "$room" %.1f) / $(fmt "$street" %.1f) | scan period 100 ms | street $(ratio "$street" 100) of it |"
echo "| ray casting at 0.2 m: M cells/s | $(fmt "$(awk -v v="$rays" 'BEGIN { if (v != "") print v / 1e6 }')" %.0f) | | |"
d=$work/decoding.csv
live=754   # VLP-16 data packets per second, single return (docs/wire-format.md §4.4)
for c in 0 2; do
  name=VLP-16; [ "$c" = 2 ] && name=HDL-32E
  dec=$(gbval "$d" "BM_PacketDecoder/capture(0=vlp16,1=dual,2=hdl32e):$c" packets/s)
  str=$(gbval "$d" "BM_PacketStream/capture(0=vlp16,1=dual,2=hdl32e):$c" packets/s)
  if [ -z "$dec" ]; then
    echo "| packet decoding, $name | skipped (no ../shared/data/real captures) | | |"
    continue
  fi
  if [ "$c" = 0 ]; then
    echo "| $name packets → points (decoder) / → scans (whole stream): k packets/s, 1 core | $(fmt "$(awk -v v="$dec" 'BEGIN{print v/1e3}')" %.0f) / $(fmt "$(awk -v v="$str" 'BEGIN{print v/1e3}')" %.0f) | live rate 0.754 k/s | $(awk -v a="$dec" -v b="$str" -v l="$live" 'BEGIN { printf("%.0f× / %.0f× live", a / l, b / l) }') |"
  else
    echo "| $name packets → points / → scans: k packets/s, 1 core | $(fmt "$(awk -v v="$dec" 'BEGIN{print v/1e3}')" %.0f) / $(fmt "$(awk -v v="$str" 'BEGIN{print v/1e3}')" %.0f) | | |"
  fi
done
