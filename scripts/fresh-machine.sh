#!/usr/bin/env bash
# Times the README's two commands as a newcomer meets them, on this machine's cores:
#   main  `scripts/run.sh` on a fresh Debian 12 (debootstrap minbase: none of ogf's packages, not even a
#         compiler), in a fresh clone of this checkout's HEAD with ../shared beside it; timed from the clone
#         to run.sh's end (its first map made, scored and drawn)
#   ci    `.ci/run` (CI=true) in a fresh clone on this host, where the packages are present
# Prints one line per command: "<name>: <seconds> s (<m>:<ss>)", and where the logs are.
#   scripts/fresh-machine.sh [--cache DIR] main|ci|both
# Needs root (debootstrap, chroot, mounts) and the Debian mirror ($OGF_DEBIAN_MIRROR, default
# http://deb.debian.org/debian). The bootstrapped system is cached in DIR (default /var/tmp/ogf-fresh) and
# copied for each run, so only the first run downloads it; the run's copy is removed afterwards.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cache=/var/tmp/ogf-fresh
mirror=${OGF_DEBIAN_MIRROR:-http://deb.debian.org/debian}
what=
while [ $# -gt 0 ]; do
  case "$1" in
    --cache) cache=$2; shift 2 ;;
    main|ci|both) what=$1; shift ;;
    -h|--help) sed -n '2,12p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fresh-machine.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -n "$what" ] || { echo "fresh-machine.sh: say main, ci or both" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || { echo "fresh-machine.sh: needs root" >&2; exit 2; }
shared=$(cd "$here/../shared" 2>/dev/null && pwd) || { echo "fresh-machine.sh: no ../shared beside $here" >&2; exit 2; }
mkdir -p "$cache"
report() { printf '%s: %d s (%d:%02d)\n' "$1" "$2" $(($2 / 60)) $(($2 % 60)); }

if [ "$what" != ci ]; then
  pristine=$cache/bookworm
  if [ ! -f "$pristine/.ogf-ready" ]; then
    echo "== debootstrap --variant=minbase bookworm from $mirror into $pristine (once)"
    rm -rf "$pristine.tmp"
    debootstrap --variant=minbase bookworm "$pristine.tmp" "$mirror" >"$cache/debootstrap.log" 2>&1 ||
      { tail -20 "$cache/debootstrap.log"; exit 1; }
    chroot "$pristine.tmp" apt-get install -y -qq --no-install-recommends git ca-certificates >"$cache/git.log" 2>&1 ||
      { tail -20 "$cache/git.log"; exit 1; }  # the newcomer's own step: they cloned the project with it
    touch "$pristine.tmp/.ogf-ready"
    mv "$pristine.tmp" "$pristine"
  fi
  root=$cache/run
  rm -rf "$root"
  cp -a "$pristine" "$root"
  cp /etc/resolv.conf "$root/etc/resolv.conf"
  mounts=()
  cleanup() {
    local m
    for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount -l "${mounts[i]}" 2>/dev/null || true; done
    rm -rf "$root"
  }
  trap cleanup EXIT
  for m in proc sys dev dev/pts dev/shm; do
    mkdir -p "$root/$m"; mount --bind "/$m" "$root/$m"; mounts+=("$root/$m")
  done
  mkdir -p "$root/work/shared"; mount --bind -o ro "$shared" "$root/work/shared"; mounts+=("$root/work/shared")
  git -C "$here" bundle create "$root/ogf.bundle" HEAD >/dev/null 2>&1
  echo "== scripts/run.sh on a fresh Debian 12 ($root), log $cache/main.log"
  start=$SECONDS
  chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 bash -c \
    'git clone -q /ogf.bundle /work/ogf && cd /work/ogf && scripts/run.sh' >"$cache/main.log" 2>&1 ||
    { tail -30 "$cache/main.log"; echo "fresh-machine.sh: run.sh failed (log $cache/main.log)"; exit 1; }
  main_s=$((SECONDS - start))
  tail -n 1 "$cache/main.log"
  report "scripts/run.sh on a fresh Debian 12" "$main_s"
fi

if [ "$what" != main ]; then
  clone=$cache/ci/ogf
  rm -rf "$cache/ci"; mkdir -p "$cache/ci"
  ln -s "$shared" "$cache/ci/shared"
  git clone -q "$here" "$clone"
  echo "== .ci/run in a fresh clone ($clone), log $cache/ci.log"
  start=$SECONDS
  (cd "$clone" && CI=true .ci/run) >"$cache/ci.log" 2>&1 ||
    { tail -30 "$cache/ci.log"; echo "fresh-machine.sh: .ci/run failed (log $cache/ci.log)"; exit 1; }
  ci_s=$((SECONDS - start))
  report ".ci/run on a fresh clone, packages present" "$ci_s"
  rm -rf "$cache/ci"
fi
