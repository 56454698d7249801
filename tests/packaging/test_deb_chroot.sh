#!/usr/bin/env bash
# Installs the package built by test_deb_contents.sh into a clean Debian 12 (debootstrap minbase) with
# apt, so apt resolves its Depends from the mirror and nothing from this machine leaks in; then runs the
# programs there (every program's libraries resolve, ogf-decode --help, ogf-mapper --print-config), imports
# the Python package after installing its Recommends python3 and python3-numpy,
# verifies the installed units with the host's systemd-analyze, removes and purges the package.
# The bootstrapped system and the downloaded .debs are cached in CACHE_DIR, so a rerun takes seconds.
# Usage: test_deb_chroot.sh DEB_DIR CACHE_DIR ; exit 77 (skip) when not root, without debootstrap or
# without the mirror ($OGF_DEBIAN_MIRROR, default http://deb.debian.org/debian).
set -u
debdir=$1; cache=$2
mirror=${OGF_DEBIAN_MIRROR:-http://deb.debian.org/debian}
skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root for debootstrap and chroot"
command -v debootstrap >/dev/null || skip "debootstrap not installed (scripts/install-deps.sh installs it)"
debs=("$debdir"/ogf_*.deb)
[ -f "${debs[0]}" ] || { echo "FAIL: no ogf_*.deb in $debdir (test_deb_contents.sh makes it)"; exit 1; }
deb=${debs[0]}
t0=$SECONDS
stage() { echo "[$((SECONDS - t0))s] $*"; }

pristine=$cache/bookworm
mkdir -p "$cache/debs"
if [ ! -f "$pristine/.ogf-ready" ]; then
  python3 -c 'import sys, urllib.request; urllib.request.urlopen(sys.argv[1], timeout=20)' \
    "$mirror/dists/bookworm/Release" 2>/dev/null || skip "mirror $mirror unreachable"
  stage "debootstrap --variant=minbase bookworm from $mirror (cached in $pristine afterwards)"
  rm -rf "$pristine.tmp"
  if ! debootstrap --variant=minbase bookworm "$pristine.tmp" "$mirror" >"$cache/debootstrap.log" 2>&1; then
    echo "FAIL: debootstrap:"; tail -20 "$cache/debootstrap.log"; exit 1
  fi
  cp /etc/resolv.conf "$pristine.tmp/etc/resolv.conf"
  chroot "$pristine.tmp" apt-get update -qq >"$cache/apt-update.log" 2>&1 ||
    { echo "FAIL: apt-get update in the new system:"; tail "$cache/apt-update.log"; exit 1; }
  touch "$pristine.tmp/.ogf-ready"
  rm -rf "$pristine" && mv "$pristine.tmp" "$pristine"
fi

root=$cache/run
rm -rf "$root"
stage "copy the clean system to $root"
cp -a "$pristine" "$root"
trap 'rm -rf "$root"' EXIT
cp /etc/resolv.conf "$root/etc/resolv.conf"
cp "$cache"/debs/*.deb "$root/var/cache/apt/archives/" 2>/dev/null
cp "$deb" "$root/tmp/"
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive LANG=C "$@"; }

stage "apt-get install ./$(basename "$deb") (Depends only, no Recommends)"
install=(apt-get install -y -q --no-install-recommends "/tmp/$(basename "$deb")")
if ! in_root "${install[@]}" >"$cache/apt-install.log" 2>&1; then
  # Stale lists after a point release: refresh once and retry.
  if ! in_root apt-get update -qq >>"$cache/apt-install.log" 2>&1; then
    skip "mirror unreachable from the chroot: $(tail -1 "$cache/apt-install.log")"
  fi
  in_root "${install[@]}" >>"$cache/apt-install.log" 2>&1 ||
    { echo "FAIL: apt-get install:"; tail -30 "$cache/apt-install.log"; exit 1; }
fi
sed -n "s/^Setting up \([^ ]*\).*/  installed \1/p" "$cache/apt-install.log"
cp "$root"/var/cache/apt/archives/*.deb "$cache/debs/" 2>/dev/null

fail=0
bad() { echo "FAIL: $*"; fail=1; }
stage "run the installed programs"
for exe in "$root"/usr/bin/ogf-*; do
  name=/usr/bin/$(basename "$exe")
  missing=$(in_root ldd "$name" 2>&1 | grep 'not found')
  [ -z "$missing" ] || bad "$name: $missing"
done
out=$(in_root ogf-decode --help 2>&1) || bad "ogf-decode --help: $out"
echo "  ogf-decode --help: $(head -1 <<<"$out")"
out=$(in_root ogf-driver --help 2>&1) || bad "ogf-driver --help: $out"
in_root test -f /usr/share/javascript/three/three.min.js || bad "libjs-three (ogf-view's three.js) not installed"
out=$(in_root ogf-mapper --print-config 2>&1) || bad "ogf-mapper --print-config: $out"
echo "  ogf-mapper --print-config: $(wc -l <<<"$out") lines"
out=$(in_root ogf-mapper --config /etc/ogf/mapper.yaml --print-config 2>&1) ||
  bad "ogf-mapper reading the packaged /etc/ogf/mapper.yaml: $out"
in_root dpkg-query -W -f='${Conffiles}\n' ogf | grep -q '/etc/ogf/driver.yaml' || bad "dpkg does not list the conffiles"

if in_root test -d /usr/lib/python3/dist-packages/ogf; then
  stage "the Python package with its Recommends (python3, python3-numpy)"
  recommends=$(dpkg-deb -f "$deb" Recommends | tr ',' '\n' | sed -n 's/^ *\(python3[a-z-]*\).*/\1/p' | sort -u)
  if in_root apt-get install -y -q --no-install-recommends $recommends >"$cache/apt-python.log" 2>&1; then
    cp "$root"/var/cache/apt/archives/*.deb "$cache/debs/" 2>/dev/null
    out=$(in_root python3 -c 'import ogf, numpy; print(ogf.NavGrid.__doc__ is not None, ogf.load_map.__doc__ is not None)' 2>&1)
    [ "$out" = "True True" ] || bad "import ogf in the installed system: $out"
    out=$(in_root python3 -c 'import ogf; ogf.load_map("/etc/ogf/mapper.yaml")' 2>&1)
    grep -q 'MapFileError: /etc/ogf/mapper.yaml' <<<"$out" || bad "ogf.load_map of a non-map: $out"
    echo "  import ogf: ok; load_map of a non-map: $(tail -1 <<<"$out")"
  else
    bad "apt-get install $recommends: $(tail -3 "$cache/apt-python.log")"
  fi
fi

stage "systemd-analyze verify the installed units"
if in_root sh -c 'command -v systemd-analyze' >/dev/null; then
  out=$(in_root systemd-analyze verify --man=no /lib/systemd/system/ogf-driver.service \
        /lib/systemd/system/ogf-mapper.service /lib/systemd/system/ogf.target 2>&1)
  [ -z "$out" ] || bad "systemd-analyze verify in the chroot: $out"
elif command -v systemd-analyze >/dev/null; then
  # minbase has no systemd: the host's checks the installed files, ExecStart pointed into the chroot.
  units=$(mktemp -d); trap 'rm -rf "$root" "$units"' EXIT
  for u in ogf-driver.service ogf-mapper.service ogf.target; do
    sed "s|^ExecStart=/usr/bin/|ExecStart=$root/usr/bin/|" "$root/lib/systemd/system/$u" >"$units/$u"
  done
  out=$(cd "$units" && SYSTEMD_LOG_LEVEL=warning systemd-analyze verify --man=no ogf-driver.service ogf-mapper.service ogf.target 2>&1)
  [ -z "$out" ] && echo "  verify: ok (host systemd-analyze)" || bad "systemd-analyze verify: $out"
else
  echo "  systemd-analyze not available here or in the chroot: not verified"
fi

stage "dpkg -r, then dpkg -P"
in_root dpkg -r ogf >"$cache/dpkg-remove.log" 2>&1 || bad "dpkg -r: $(tail -5 "$cache/dpkg-remove.log")"
[ ! -e "$root/usr/bin/ogf-driver" ] || bad "dpkg -r left /usr/bin/ogf-driver"
[ -f "$root/etc/ogf/driver.yaml" ] || bad "dpkg -r removed the conffile /etc/ogf/driver.yaml"
in_root dpkg -P ogf >>"$cache/dpkg-remove.log" 2>&1 || bad "dpkg -P: $(tail -5 "$cache/dpkg-remove.log")"
[ ! -e "$root/etc/ogf/driver.yaml" ] || bad "dpkg -P left /etc/ogf/driver.yaml"
stage "done"
exit $fail
