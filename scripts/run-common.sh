# Pieces scripts/run.sh, scripts/run-sources.sh and scripts/wire.sh share (sourced, not run).

# sim_extrinsic DIR: the sensor's mount that ogf-sim wrote into DIR/sim.yaml, as the mapper's extrinsic
# ({translation: [...], quaternion: [...]}); fails, saying so, when sim.yaml holds none.
sim_extrinsic() {
  local e
  e=$(sed -n 's/^sensor_to_body: {xyz: \(\[[^]]*\]\), quaternion_wxyz: \(\[[^]]*\]\)}.*/translation: \1, quaternion: \2/p' "$1/sim.yaml")
  if [ -z "$e" ]; then echo "${0##*/}: no sensor_to_body in $1/sim.yaml" >&2; return 1; fi
  echo "{$e}"
}

# wait_for_quiet_client LOG: waits (at most 120 s) until the sequence ogf-map-client --progress writes to
# LOG has not moved for 3 s: the mapper has drained its queue and the client has what it published.
wait_for_quiet_client() {
  local last= same=0 now
  for _ in $(seq 1 120); do
    sleep 1
    now=$(grep '^seq ' "$1" | tail -n 1 | cut -d' ' -f2)
    if [ -n "$now" ] && [ "$now" = "$last" ]; then same=$((same + 1)); else same=0; fi
    last=$now
    if [ "$same" -ge 3 ]; then return 0; fi
  done
}

# finish_run BIN OUT MAP [OGF-MAP ARGS...]: what every mode of run.sh leaves beside its map. From MAP (a map
# file or the mapper's snapshot), ogf-map --from-map writes the 2-D navigation grid (OUT/nav: map_server's
# map.pgm and map.yaml) and the map as an OctoMap tree (OUT/map.bt, for octovis), with the further ogf-map
# arguments given (e.g. --nav-floor-z); then the outputs are listed, the caller adds its own lines and ends
# with "outputs: OUT". Fails, naming its log, when ogf-map does or an output is missing.
finish_run() {
  local bin=$1 out=$2 map=$3 f
  shift 3
  if ! "$bin/ogf-map" --from-map "$map" --export-nav "$out/nav" --export-bt "$out/map.bt" "$@" \
       >"$out/logs/nav.log" 2>&1; then
    echo "${0##*/}: ogf-map --from-map $map failed (see $out/logs/nav.log)" >&2; return 1
  fi
  for f in "$map" "$out/map_occupied.ply" "$out/map.bt" "$out/nav/map.pgm" "$out/nav/map.yaml" "$out/accuracy.txt" \
           "$out/png/occupancy.png" "$out/png/entropy.png"; do
    if [ ! -s "$f" ]; then echo "${0##*/}: the run left no $f" >&2; return 1; fi
  done
  echo
  echo "map:        $map"
  echo "PLY:        $out/map_occupied.ply (occupied cells, for CloudCompare or Open3D)"
  echo "PNG:        $out/png/ ($(cd "$out/png" && ls -- *.png | tr '\n' ' ' | sed 's/ $//'))"
  echo "accuracy:   $out/accuracy.txt"
  echo "OctoMap:    $out/map.bt (the map as an OctoMap tree, for octovis)"
  if [ -s "$out/octomap.bt" ]; then
    echo "            $out/octomap.bt (OctoMap's own map of the same rays, the baseline in accuracy.txt)"
  fi
  echo "nav grid:   $out/nav/map.pgm $out/nav/map.yaml (for nav2/map_server): $(grep -m1 -o 'nav: map.pgm.*' "$out/logs/nav.log" | sed 's/^nav: //')"
  echo "logs:       $out/logs/"
}

# port_free udp|tcp PORT: no socket on this host is bound to PORT.
port_free() { [ -z "$(ss -Hln "--$1" "sport = :$2" 2>/dev/null)" ]; }

# pick_run_slot: the first k in 0..49 whose ports are all free: the LCM bus port 7689+k, the sensor's data
# and position ports 12368+2k and 18308+2k (UDP), ogf-view's 8765+k (TCP).
pick_run_slot() {
  local k
  for k in $(seq 0 49); do
    if port_free udp $((7689 + k)) && port_free udp $((12368 + 2 * k)) && port_free udp $((18308 + 2 * k)) &&
       port_free tcp $((8765 + k)); then
      echo "$k"; return 0
    fi
  done
  return 1
}
