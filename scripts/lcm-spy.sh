#!/usr/bin/env bash
# lcm-spy with ogf's types loaded and a receive buffer that holds whole scans, so every channel shows its
# true rate; --text prints the same table each second without a window (over ssh, on the robot).
#
#   scripts/lcm-spy.sh [--lcm-url URL] [--buffer BYTES] [--text [--duration S]]
#
# Java LCM 1.3.1 ignores the URL's recv_buf_size and keeps the kernel's default receive buffer
# (net.core.rmem_default, 212992 bytes on Debian): a decoded scan (~690 KB, a dozen UDP fragments) does not
# fit, so plain lcm-spy sees one scan in ten. The launcher (ogf.spy.Main, ogf_spy.jar) asks for BYTES
# (default 16 MiB, or recv_buf_size of the URL) on lcm-spy's socket, and this raises net.core.rmem_max,
# which caps it, when run as root. The jars come from $OGF_JAVA_DIR, else build/share/java, else the
# installed share/java.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
buffer=""
text=""
args=()
usage() { sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --buffer) buffer=$2; args+=(--buffer "$2"); shift 2 ;;
    --text) text=1; args+=("$1"); shift ;;
    -h|--help) usage; exit 0 ;;
    *) args+=("$1"); shift ;;
  esac
done

# lcm-spy's window needs a display; without one Java would only print a HeadlessException. (The launcher
# checks again: a display that is set but cannot be opened gets the same advice.)
if [ -z "$text" ] && [ -z "${DISPLAY:-}" ] && [ -z "${WAYLAND_DISPLAY:-}" ]; then
  echo "lcm-spy.sh: no display to open lcm-spy's window on (DISPLAY and WAYLAND_DISPLAY are unset)." \
       "Over ssh or on the robot, run: $0 --text (the same table each second, no window), or log in with ssh -X." >&2
  exit 1
fi

dir=""
for candidate in ${OGF_JAVA_DIR:+"$OGF_JAVA_DIR"} "${OGF_BUILD_DIR:-$here/build}/share/java" "$here/share/java" \
                 /usr/local/share/java /usr/share/java; do
  if [ -f "$candidate/lcmtypes_ogf.jar" ] && [ -f "$candidate/ogf_spy.jar" ]; then dir=$candidate; break; fi
done
if [ -z "$dir" ]; then
  echo "lcm-spy.sh: lcmtypes_ogf.jar and ogf_spy.jar not found; build first (scripts/build.sh) or set OGF_JAVA_DIR" >&2
  exit 1
fi
command -v java >/dev/null || { echo "lcm-spy.sh: java not found (apt-get install default-jre)" >&2; exit 1; }
[ -f /usr/share/java/lcm.jar ] || { echo "lcm-spy.sh: /usr/share/java/lcm.jar missing (apt-get install liblcm-java)" >&2; exit 1; }
[ -f /usr/share/java/jchart2d.jar ] || echo "lcm-spy.sh: warning: libjchart2d-java is missing, charts will not work" >&2

# The buffer the launcher will ask for: --buffer, else the URL's recv_buf_size, else 16 MiB.
if [ -z "$buffer" ]; then
  buffer=$(printf '%s\n' "${args[@]}" "${LCM_DEFAULT_URL:-}" | sed -nE 's/.*[?&]recv_buf_size=([0-9]+).*/\1/p' | head -n 1)
  buffer=${buffer:-16777216}
fi
rmem_max=$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)
if [ "$buffer" -gt 0 ] && [ "$rmem_max" -lt "$buffer" ]; then
  if [ -w /proc/sys/net/core/rmem_max ] && echo "$buffer" > /proc/sys/net/core/rmem_max 2>/dev/null; then
    echo "lcm-spy.sh: raised net.core.rmem_max from $rmem_max to $buffer"
  else
    echo "lcm-spy.sh: warning: the kernel caps receive buffers at net.core.rmem_max=$rmem_max bytes, less than" \
         "the $buffer asked for; scans may be lost. Fix: sudo sysctl -w net.core.rmem_max=$buffer" >&2
  fi
fi

# java directly, not Debian's lcm-spy wrapper: the wrapper passes -Xincgc, which JDK 17 refuses
# (lcm-proj/lcm#331). lcm-spy's type database finds the types on the class path.
exec java -Djava.net.preferIPv4Stack=true -Xmx128m -Xms64m -ea \
  -cp "/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$dir/lcmtypes_ogf.jar:$dir/ogf_spy.jar" \
  ogf.spy.Main "${args[@]}"
