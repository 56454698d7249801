#!/usr/bin/env bash
# Builds the Debian package with CPack in the build tree and checks it: control fields (name, version,
# Depends computed by dpkg-shlibdeps naming the libraries the programs link), every installed program
# and only those, units where systemd looks and agreeing with the programs' paths, /etc/ogf conffiles,
# the LCM jar, docs, the Python package (when built), maintainer scripts that enable nothing; lintian errors
# fail when lintian is present.
# Usage: test_deb_contents.sh BUILD_DIR OUT_DIR VERSION ; exit 77 (skip) without Debian's tools.
# Expected programs: every BUILD_DIR/bin/ogf-* except the benchmarks (ogf-bench-*).
set -u
build=$1; out=$2; version=$3
programs=()
for exe in "$build"/bin/ogf-*; do
  [[ -x "$exe" && "$exe" != */ogf-bench-* ]] && programs+=("$(basename "$exe")")
done
[ ${#programs[@]} -gt 0 ] || { echo "FAIL: no programs in $build/bin"; exit 1; }
for tool in cpack dpkg-deb dpkg-shlibdeps; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool not installed (dpkg-dev)"; exit 77; }
done
fail=0
bad() { echo "FAIL: $*"; fail=1; }

rm -rf "$out" && mkdir -p "$out"
if ! (cd "$build" && cpack -G DEB -B "$out" >"$out/cpack.log" 2>&1); then
  echo "FAIL: cpack:"; tail -30 "$out/cpack.log"; exit 1
fi
debs=("$out"/ogf_*.deb)
[ -f "${debs[0]}" ] || { echo "FAIL: cpack made no ogf_*.deb in $out"; ls "$out"; exit 1; }
deb=${debs[0]}
echo "package: $deb ($(stat -c %s "$deb") bytes)"

info=$(dpkg-deb -I "$deb"); echo "$info" | sed -n '/^ [A-Z][A-Za-z-]*: /p'
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = ogf ] || bad "Package is '$(field Package)'"
[[ "$(field Version)" == "$version"-* ]] || bad "Version '$(field Version)' is not $version-<release>"
[ "$(field Architecture)" = "$(dpkg --print-architecture)" ] || bad "Architecture '$(field Architecture)'"
[ -n "$(field Maintainer)" ] && [ -n "$(field Section)" ] || bad "Maintainer or Section missing"
depends=$(field Depends)
for lib in libc6 libstdc++6 liblcm libpcap libsqlite3 libspdlog libfmt libyaml-cpp libjs-three; do
  grep -q "\b$lib" <<<"$depends" || bad "Depends lacks $lib: $depends"
done
grep -Eq -- '-dev( |,|$)' <<<"$depends" && bad "Depends names a -dev package: $depends"

files=$(dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|')
has() { grep -qx "$1" <<<"$files" || bad "missing $1"; }
for p in "${programs[@]}"; do has "/usr/bin/$p"; done
extra=$(grep '^/usr/bin/.' <<<"$files" | sed 's|/usr/bin/||' | grep -vxF -f <(printf '%s\n' "${programs[@]}"))
[ -z "$extra" ] || bad "unexpected programs (tests or benchmarks?) in /usr/bin: $extra"
grep -q '\.a$\|/include/\|/tests\?/' <<<"$files" && bad "static libraries, headers or tests packaged"
for f in /lib/systemd/system/ogf-driver.service /lib/systemd/system/ogf-mapper.service \
         /lib/systemd/system/ogf.target /etc/ogf/driver.yaml /etc/ogf/mapper.yaml \
         /usr/lib/sysctl.d/60-ogf-lcm.conf /usr/share/java/lcmtypes_ogf.jar /usr/share/java/ogf_spy.jar \
         /usr/share/doc/ogf/README.md \
         /usr/share/doc/ogf/copyright /usr/share/doc/ogf/changelog.Debian.gz \
         /usr/share/doc/ogf/examples/ogf-driver.service.d/pcap-live.conf; do
  has "$f"
done

control=$(mktemp -d); data=$(mktemp -d); trap 'rm -rf "$control" "$data"' EXIT
dpkg-deb -e "$deb" "$control"; dpkg-deb -x "$deb" "$data"
diff <(sort "$control/conffiles") <(printf '/etc/ogf/driver.yaml\n/etc/ogf/mapper.yaml\n') >/dev/null ||
  bad "conffiles: $(tr '\n' ' ' <"$control/conffiles")"
for s in postinst prerm postrm; do
  [ -x "$control/$s" ] || bad "no executable $s"
  grep -Eq '^[^#]*(systemctl|deb-systemd-invoke|deb-systemd-helper)[^#]*\b(enable|start)\b' "$control/$s" && bad "$s enables or starts a unit"
done
# The units run what the package installs and read the configuration it installs.
for unit in ogf-driver ogf-mapper; do
  exe=$(sed -n 's/^ExecStart=\([^ ]*\).*/\1/p' "$data/lib/systemd/system/$unit.service")
  [ -x "$data$exe" ] || bad "$unit.service runs $exe, which the package does not install"
  conf=$(grep -o '\${CONFIGURATION_DIRECTORY}/[a-z]*\.yaml' "$data/lib/systemd/system/$unit.service" | sed 's|.*/||')
  grep -q '^ConfigurationDirectory=ogf$' "$data/lib/systemd/system/$unit.service" && [ -f "$data/etc/ogf/$conf" ] ||
    bad "$unit.service reads /etc/ogf/$conf, which the package does not install"
done
# The Python package, when the build made it: where Debian's python3 looks, with numpy recommended.
if compgen -G "$build/python/ogf/_ogf*.so" >/dev/null; then
  has /usr/lib/python3/dist-packages/ogf/__init__.py
  grep -q '^/usr/lib/python3/dist-packages/ogf/_ogf\.cpython-[0-9]*-.*\.so$' <<<"$files" ||
    bad "no extension module /usr/lib/python3/dist-packages/ogf/_ogf.cpython-*.so"
  grep -q 'python3-numpy' <<<"$(field Recommends)" || bad "Recommends lacks python3-numpy: $(field Recommends)"
fi
echo "files: $(grep -c '[^/]$' <<<"$files") ($(grep -c '^/usr/bin/.' <<<"$files") programs)"

if command -v lintian >/dev/null; then
  lint=$(lintian --tag-display-limit 0 "$deb" 2>&1); echo "lintian:"; echo "$lint" | sed 's/^/  /'
  grep -q '^E:' <<<"$lint" && bad "lintian reports errors"
else
  echo "lintian not installed: not run"
fi
exit $fail
