#!/usr/bin/env bash
# Routes LCM's udpm multicast (224.0.0.0/4) over the loopback interface, so the daemons and the
# integration tests talk on this host only (ttl=0). Needs root (or CAP_NET_ADMIN); a no-op when the
# route is already there. A robot whose only NIC is the lidar LAN needs the same route.
set -euo pipefail
if ip route get 239.255.76.67 2>/dev/null | grep -q ' dev lo'; then exit 0; fi
if [ "$(id -u)" -ne 0 ]; then
  echo "multicast-loopback: no multicast route over lo; run as root: ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo" >&2
  exit 1
fi
ip link set lo multicast on
ip route replace 224.0.0.0/4 dev lo
echo "multicast-loopback: 224.0.0.0/4 now routed over lo"
