# Sourced by the tests of scripts/run.sh's modes: check_run_outputs OUT RUN_LOG MAP checks that a run left
# what every mode leaves (scripts/run-common.sh, finish_run), each file readable as what it claims to be, every
# picture of png/ the same size (they cover the same area), and that the run's last line names OUT.

# png_size FILE: "WIDTH HEIGHT" from the PNG's IHDR.
png_size() {
  local w h
  w=$(od -An -tu1 -j16 -N4 "$1" | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')
  h=$(od -An -tu1 -j20 -N4 "$1" | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')
  echo "$w $h"
}

check_run_outputs() {
  local out=$1 log=$2 map=$3 f first= size
  for f in "$map" map_occupied.ply map.bt nav/map.pgm nav/map.yaml accuracy.txt png/occupancy.png png/entropy.png; do
    [ -s "$out/$f" ] || { echo "FAIL: the run left no $out/$f"; return 1; }
  done
  [ "$(head -c 3 "$out/map_occupied.ply")" = ply ] || { echo "FAIL: map_occupied.ply is not a PLY file"; return 1; }
  head -n 1 "$out/map.bt" | grep -q '^# Octomap OcTree binary file' || { echo "FAIL: map.bt is not an OctoMap .bt"; return 1; }
  [ "$(head -c 2 "$out/nav/map.pgm")" = P5 ] || { echo "FAIL: nav/map.pgm is not a binary PGM"; return 1; }
  grep -q '^image: map.pgm' "$out/nav/map.yaml" || { echo "FAIL: nav/map.yaml does not name map.pgm"; return 1; }
  for f in "$out"/png/*.png; do
    [ "$(head -c 4 "$f" | tail -c 3)" = PNG ] || { echo "FAIL: $f is not a PNG"; return 1; }
    size=$(png_size "$f")
    if [ -z "$first" ]; then first="$size ($(basename "$f"))"; continue; fi
    [ "$size" = "${first%% (*}" ] || { echo "FAIL: $(basename "$f") is $size pixels, $first"; return 1; }
  done
  [ "$(tail -n 1 "$log")" = "outputs:    $out" ] ||
    { echo "FAIL: the run's last line is '$(tail -n 1 "$log")', not 'outputs:    $out'"; return 1; }
  echo "outputs: $(cd "$out" && ls -d -- "$map" map_occupied.ply map.bt nav png/*.png accuracy.txt | tr '\n' ' ')"
}
