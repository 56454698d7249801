#!/usr/bin/env bash
# Stand-in hosts for LCM across machines: one Linux network namespace per host, so a single computer can
# run the mapper, the drivers and the map clients as if each were on its own machine, with LCM's udpm
# multicast crossing a real (virtual) Ethernet link. It is also the recipe for real hosts: what each
# "host" gets here is what a real one needs (see docs/multi-host.md).
#
#   scripts/netns-hosts.sh up   NAME [--routed] [--vxlan] HOST...   # creates NAME-HOST per host
#   scripts/netns-hosts.sh down NAME                                # removes every NAME-* namespace
#   ip netns exec NAME-HOST COMMAND ...                             # runs COMMAND on that host
#
# Topologies (NAME-net is the network between the hosts: a switch, or a router):
#   (default)  one LAN: every host has a veth to a Linux bridge in NAME-net, 10.77.0.N/24 (N = 1, 2, ...
#              in the order given). udpm with ttl=1 reaches every host: the bridge floods multicast.
#   --routed   every host on its own subnet 10.77.N.1/24 behind a router in NAME-net (10.77.N.254, IP
#              forwarding on, no multicast routing): unicast crosses, LCM's multicast does not, as
#              between two sites or across the Internet.
#   --vxlan    adds an Ethernet tunnel (VXLAN, VNI 77, UDP 4789) between all hosts over whichever network
#              was chosen, each with overlay address 10.78.0.N/24 and one flood entry per other host
#              (head-end replication, so the underlay needs only unicast); LCM's multicast is routed into
#              the tunnel and so reaches every host, even over --routed. Its MTU is 1450: the 50 bytes
#              of VXLAN, UDP, IP and Ethernet headers then fit a 1500-byte frame of the network below.
# On every host: lo up, multicast on, the route 224.0.0.0/4 on the interface LCM must use (LCM has no
# interface option: the routing table chooses). net.core.rmem_max is the machine's (not per namespace):
# raise it once, `sysctl -w net.core.rmem_max=16777216`, for the recv_buf_size=8388608 the URLs ask for.
#
# Needs root (CAP_NET_ADMIN and CAP_SYS_ADMIN) and iproute2. Exit 0 on success; 1 with the step that failed
# (call `down NAME` to clean up: it removes whatever part exists); 2 on bad usage. NAME is at most 8
# characters of [a-z0-9] so that interface names fit the kernel's 15.
set -uo pipefail

usage() { echo "usage: $0 up NAME [--routed] [--vxlan] HOST... | down NAME" >&2; exit 2; }
die() { echo "netns-hosts: $*" >&2; exit 1; }

down() {
  local name=$1 ns
  for ns in $(ip netns list 2>/dev/null | awk '{print $1}'); do
    # Deleting a namespace deletes the veth ends in it, and with them their peers.
    case $ns in "$name"-*) ip netns del "$ns" 2>/dev/null ;; esac
  done
}

# Host end of a link: lo up, the address, the link up with multicast, and sysctls.
host_setup() {  # namespace interface address/prefix
  ip -n "$1" link set lo up &&
    ip -n "$1" addr add "$3" dev "$2" &&
    ip -n "$1" link set "$2" up multicast on
}

up() {
  local name=$1; shift
  local routed=0 vxlan=0 hosts=()
  while [ $# -gt 0 ]; do
    case $1 in
      --routed) routed=1 ;;
      --vxlan) vxlan=1 ;;
      -*) usage ;;
      *) hosts+=("$1") ;;
    esac
    shift
  done
  [[ $name =~ ^[a-z0-9]{1,8}$ ]] || die "NAME must be 1 to 8 characters of [a-z0-9]: '$name'"
  [ ${#hosts[@]} -ge 1 ] || usage
  [ ${#hosts[@]} -le 50 ] || die "at most 50 hosts"
  command -v ip >/dev/null || die "iproute2 (ip) is not installed"
  local net=$name-net
  ip netns add "$net" || die "cannot create the network namespace $net (root or CAP_SYS_ADMIN needed)"
  ip -n "$net" link set lo up
  if [ $routed = 0 ]; then
    ip -n "$net" link add br0 type bridge || die "cannot create a bridge in $net"
    ip -n "$net" link set br0 up || die "cannot bring the bridge up"
  else
    ip netns exec "$net" sysctl -qw net.ipv4.ip_forward=1 || die "cannot turn IP forwarding on in $net"
  fi
  local i=0 h ns under=()
  for h in "${hosts[@]}"; do
    i=$((i + 1))
    [[ $h =~ ^[a-z0-9]{1,12}$ ]] || die "HOST must be 1 to 12 characters of [a-z0-9]: '$h'"
    ns=$name-$h
    ip netns add "$ns" || die "cannot create the network namespace $ns"
    # Interface names: eth0 inside the host; the peer is created in NAME-net directly, so no name clash
    # with the caller's namespace.
    ip -n "$ns" link add eth0 type veth peer name "p$i" netns "$net" || die "cannot create a veth pair for $h"
    if [ $routed = 0 ]; then
      ip -n "$net" link set "p$i" master br0 up || die "cannot attach $h to the bridge"
      host_setup "$ns" eth0 "10.77.0.$i/24" || die "cannot configure $h"
      under+=("10.77.0.$i")
    else
      ip -n "$net" addr add "10.77.$i.254/24" dev "p$i" && ip -n "$net" link set "p$i" up || die "cannot configure the router's port to $h"
      host_setup "$ns" eth0 "10.77.$i.1/24" || die "cannot configure $h"
      ip -n "$ns" route add default via "10.77.$i.254" || die "cannot route $h through the router"
      under+=("10.77.$i.1")
    fi
  done
  i=0
  for h in "${hosts[@]}"; do
    i=$((i + 1))
    ns=$name-$h
    if [ $vxlan = 0 ]; then
      ip -n "$ns" route add 224.0.0.0/4 dev eth0 || die "cannot route multicast over eth0 on $h"
      continue
    fi
    # The tunnel: unicast VXLAN to every other host; the zero MAC entries flood broadcast, unknown and
    # multicast frames (LCM's) to each of them.
    ip -n "$ns" link add vx0 type vxlan id 77 dstport 4789 local "${under[$((i - 1))]}" nolearning ||
      die "cannot create a VXLAN interface on $h (kernel module vxlan missing?)"
    local j=0 other
    for other in "${under[@]}"; do
      j=$((j + 1))
      [ $j = $i ] && continue
      ip netns exec "$ns" bridge fdb append 00:00:00:00:00:00 dev vx0 dst "$other" || die "cannot add $other to $h's tunnel"
    done
    ip -n "$ns" addr add "10.78.0.$i/24" dev vx0 &&
      ip -n "$ns" link set vx0 mtu 1450 up multicast on &&
      ip -n "$ns" route add 224.0.0.0/4 dev vx0 || die "cannot route multicast into the tunnel on $h"
  done
  i=0
  for h in "${hosts[@]}"; do
    i=$((i + 1))
    local via=eth0 addr=${under[$((i - 1))]}
    [ $vxlan = 1 ] && via=vx0 addr=10.78.0.$i
    echo "$name-$h: $addr, LCM multicast over $via"
  done
}

[ $# -ge 2 ] || usage
case $1 in
  up) shift; up "$@" ;;
  down) [ $# = 2 ] || usage; down "$2" ;;
  *) usage ;;
esac
