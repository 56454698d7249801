#!/usr/bin/env bash
# Records the LCM bus with lcm-logger so that a drive at the sensor's full rate loses nothing, then prints
# what the log holds per channel and checks it (scripts/lcm_log_check.py; exit 1 when something is
# missing). Stop it with Ctrl-C, or give --duration.
#
#   scripts/record.sh [--lcm-url URL] [--channels REGEX] [--duration S] [--buffer BYTES] FILE.lcmlog
#
# Losses come from the kernel's socket receive buffer: lcm-logger's default (rmem_default, 212992 bytes
# on Debian) holds less than one decoded scan. This asks for BYTES (default 16 MiB) through the URL's
# recv_buf_size, and raises net.core.rmem_max, which caps it, when run as root.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
url=${LCM_DEFAULT_URL:-udpm://239.255.76.67:7667?ttl=0}
channels=".*"
duration=""
buffer=16777216
out=""
usage() { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --lcm-url) url=$2; shift 2 ;;
    --lcm-url=*) url=${1#*=}; shift ;;
    --channels) channels=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --buffer) buffer=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "record.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) [ -z "$out" ] || { echo "record.sh: one output file, got $out and $1" >&2; exit 2; }; out=$1; shift ;;
  esac
done
[ -n "$out" ] || { echo "record.sh: name the log file to write" >&2; usage >&2; exit 2; }
command -v lcm-logger >/dev/null || { echo "record.sh: lcm-logger not found (apt-get install liblcm-bin)" >&2; exit 1; }

case "$url" in
  udpm://*)
    url=$(printf '%s' "$url" | sed -E 's/[?&]recv_buf_size=[0-9]+//')
    case "$url" in *\?*) url="$url&recv_buf_size=$buffer" ;; *) url="$url?recv_buf_size=$buffer" ;; esac
    rmem_max=$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)
    if [ "$rmem_max" -lt "$buffer" ]; then
      if [ -w /proc/sys/net/core/rmem_max ] && echo "$buffer" > /proc/sys/net/core/rmem_max 2>/dev/null; then
        echo "record.sh: raised net.core.rmem_max from $rmem_max to $buffer"
      else
        echo "record.sh: warning: the kernel caps receive buffers at net.core.rmem_max=$rmem_max bytes, less than" \
             "the $buffer asked for; bursts may be lost. Fix: sudo sysctl -w net.core.rmem_max=$buffer" >&2
      fi
    fi
    ;;
esac

echo "record.sh: recording '$channels' from $url into $out"
# A logger starved of CPU drops what its buffer cannot hold: run it at the normal priority even when this
# script was started niced (root only may lower the niceness). -l is broken in Debian's LCM 1.3.1: the
# long option only.
niceness=$(nice)
if [ "$(id -u)" = 0 ] && [ "$niceness" -gt 0 ]; then boost=(nice -n "-$niceness"); else boost=(); fi
"${boost[@]}" lcm-logger --lcm-url="$url" -c "$channels" -f -q "$out" &
logger=$!
stop() { kill -INT "$logger" 2>/dev/null || true; }
trap stop INT TERM
if [ -n "$duration" ]; then
  sleep "$duration" &
  sleeper=$!
  trap 'stop; kill $sleeper 2>/dev/null || true' INT TERM
  wait "$sleeper" 2>/dev/null || true
  stop
fi
# wait returns early when a trapped signal arrives; wait again until the logger has closed the file.
while kill -0 "$logger" 2>/dev/null; do wait "$logger" 2>/dev/null || true; done
trap - INT TERM
[ -f "$out" ] || { echo "record.sh: lcm-logger wrote no $out" >&2; exit 1; }
python3 "$here/lcm_log_check.py" "$out"
