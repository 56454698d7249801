#!/usr/bin/env python3
"""Prints what an LCM log holds per channel (messages, bytes, span, rate, the longest silence) and checks it
is complete: VELODYNE_SCAN sequence numbers without gaps, as many VELODYNE_SCAN as the driver says it
published while the log ran (VELODYNE_STATUS scans_published), and as many VELODYNE_PACKETS as scans (in a
log of the packets without the scans: as many VELODYNE_PACKETS as the driver says it published scans).
Exits 1 when something is missing, 0 otherwise.

Usage: scripts/lcm_log_check.py LOG [--scan-channel C] [--packets-channel C] [--status-channel C]

The log format is lcm-logger's (lcm/eventlog.c): per event a 0xEDA1DA01 sync word, event number, timestamp
(us), channel and data lengths, channel, data. Message fields are read at their offsets in
messages/lcmtypes: lidar_scan_t starts (after its 8-byte fingerprint) utime, seq; driver_status_t starts
utime, string source, model, return_mode, 3 floats, then int64 counters of which scans_published is the 8th."""
import argparse
import struct
import sys

SYNC = 0xEDA1DA01


def events(path):
    with open(path, "rb") as f:
        data = f.read()
    at = 0
    while at + 28 <= len(data):
        sync, _, utime, clen, dlen = struct.unpack_from(">IqqII", data, at)
        if sync != SYNC:
            raise SystemExit(f"{path}: no sync word at byte {at}: not an LCM log, or damaged")
        at += 28
        channel = data[at:at + clen].decode(errors="replace")
        at += clen
        yield channel, utime, data[at:at + dlen]
        at += dlen


def scan_seq(b):
    return struct.unpack_from(">q", b, 16)[0] if len(b) >= 24 else None


def scans_published(b):
    try:
        (n,) = struct.unpack_from(">i", b, 16)
        return struct.unpack_from(">9q", b, 20 + n + 2 + 12)[7]
    except struct.error:
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("log")
    ap.add_argument("--scan-channel", default="VELODYNE_SCAN")
    ap.add_argument("--packets-channel", default="VELODYNE_PACKETS")
    ap.add_argument("--status-channel", default="VELODYNE_STATUS")
    a = ap.parse_args()

    per = {}
    seqs, published = [], []
    for channel, utime, payload in events(a.log):
        c = per.setdefault(channel, {"n": 0, "bytes": 0, "first": utime, "last": utime, "gap": 0})
        c["n"] += 1
        c["bytes"] += len(payload)
        c["gap"] = max(c["gap"], utime - c["last"])
        c["last"] = utime
        if channel == a.scan_channel:
            seqs.append(scan_seq(payload))
        elif channel == a.status_channel:
            published.append(scans_published(payload))

    if not per:
        print(f"{a.log}: empty: nothing was recorded (is anything publishing on this bus?)")
        return 1
    print(f"{'channel':<24} {'messages':>9} {'MB':>9} {'seconds':>8} {'Hz':>8} {'longest gap s':>14}")
    for channel in sorted(per):
        c = per[channel]
        span = (c["last"] - c["first"]) / 1e6
        rate = (c["n"] - 1) / span if span > 0 else 0.0
        print(f"{channel:<24} {c['n']:>9} {c['bytes'] / 1e6:>9.2f} {span:>8.2f} {rate:>8.2f} {c['gap'] / 1e6:>14.3f}")

    missing = 0
    if seqs:
        s = sorted(x for x in seqs if x is not None)
        lost = (s[-1] - s[0] + 1) - len(set(s))
        print(f"{a.scan_channel}: seq {s[0]} .. {s[-1]}, {lost} missing")
        missing += lost
        known = [p for p in published if p is not None]
        if len(known) >= 2:
            # Scans published between the first and the last status both in the log; the first status may
            # come a scan before or after the first recorded scan, hence the tolerance of one at each end.
            window = known[-1] - known[0]
            recorded_in_window = len(s)
            if recorded_in_window + 2 < window:
                print(f"{a.scan_channel}: the driver published {window} scans between its first and last status, "
                      f"the log holds {recorded_in_window}")
                missing += window - recorded_in_window
        packets = per.get(a.packets_channel, {}).get("n", 0)
        if packets and abs(packets - len(s)) > 1:
            print(f"{a.packets_channel}: {packets} messages for {len(s)} scans")
            missing += abs(packets - len(s))
    elif a.packets_channel in per:
        # A log of the raw packets without the scans: one batch per scan the driver published.
        known = [p for p in published if p is not None]
        batches = per[a.packets_channel]["n"]
        if len(known) >= 2:
            window = known[-1] - known[0]
            if batches + 2 < window:
                print(f"{a.packets_channel}: the driver published {window} scans between its first and last status, "
                      f"the log holds {batches} packet batches")
                missing += window - batches
        else:
            print(f"{a.packets_channel}: {batches} packet batches (record {a.status_channel} too to check none is "
                  f"missing)")
    if missing:
        print(f"{a.log}: INCOMPLETE: {missing} messages missing")
        return 1
    print(f"{a.log}: complete")
    return 0


if __name__ == "__main__":
    sys.exit(main())
