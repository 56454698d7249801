#!/usr/bin/env python3
"""Counts the bytes each LCM channel carries, from an lcm-logger stream (a file or a FIFO lcm-logger writes
to, so nothing is stored), and prints per channel: messages, MB, the mean bytes per second over --seconds
(default: the channel's own span) and the busiest second.

Usage: scripts/lcm_bytes.py LOG [--seconds S] [--channels REGEX] [--json]

The log format is lcm-logger's (lcm/eventlog.c): per event a 0xEDA1DA01 sync word, event number, timestamp
(us), channel and data lengths, channel, data. A message's bytes are its data (the encoded message, as LCM
puts it in its UDP datagrams, which add a few tens of bytes of header each)."""
import argparse
import json
import re
import struct
import sys

SYNC = 0xEDA1DA01


def read_exact(f, n):
    buf = b""
    while len(buf) < n:
        chunk = f.read(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return buf


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("log")
    p.add_argument("--seconds", type=float, default=0.0, help="divide by this instead of each channel's span")
    p.add_argument("--channels", default=".*", help="only channels matching this regex")
    p.add_argument("--json", action="store_true", help="one JSON object instead of the table")
    a = p.parse_args()
    keep = re.compile(a.channels)
    stats = {}
    with open(a.log, "rb", buffering=1 << 20) as f:
        while True:
            head = read_exact(f, 28)
            if head is None:
                break
            sync, _, utime, clen, dlen = struct.unpack(">IqqII", head)
            if sync != SYNC:
                sys.exit(f"{a.log}: no sync word: not an LCM log, or damaged")
            channel = read_exact(f, clen).decode(errors="replace")
            # The data is skipped in slices: a keyframe or scan message is hundreds of kB.
            left = dlen
            while left > 0:
                got = f.read(min(left, 1 << 20))
                if not got:
                    break
                left -= len(got)
            if not keep.fullmatch(channel):
                continue
            c = stats.setdefault(channel, {"messages": 0, "bytes": 0, "first": utime, "last": utime, "per_s": {}})
            c["messages"] += 1
            c["bytes"] += dlen
            c["last"] = utime
            second = utime // 1_000_000
            c["per_s"][second] = c["per_s"].get(second, 0) + dlen
    out = {}
    for channel, c in sorted(stats.items()):
        span = a.seconds if a.seconds > 0 else max((c["last"] - c["first"]) / 1e6, 1e-6)
        out[channel] = {"messages": c["messages"], "bytes": c["bytes"], "bytes_per_s": c["bytes"] / span,
                        "peak_bytes_per_s": max(c["per_s"].values())}
    if a.json:
        print(json.dumps(out))
        return
    print(f"{'channel':<24} {'messages':>9} {'MB':>10} {'MB/s':>9} {'busiest s MB':>13}")
    for channel, c in out.items():
        print(f"{channel:<24} {c['messages']:>9} {c['bytes'] / 1e6:>10.2f} {c['bytes_per_s'] / 1e6:>9.3f} "
              f"{c['peak_bytes_per_s'] / 1e6:>13.3f}")


if __name__ == "__main__":
    main()
