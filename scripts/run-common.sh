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
