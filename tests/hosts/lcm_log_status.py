#!/usr/bin/env python3
"""Prints the last OGF_MAPPER_STATUS and VELODYNE_STATUS* counters found in an LCM log file (lcm-logger's
format: per event a 0xEDA1DA01 sync word, event number, timestamp, channel and data lengths, channel, data;
lcm/eventlog.c), as `key value` lines. The fields are read at their offsets in messages/lcmtypes: after the
8-byte fingerprint, mapper_status_t holds 10 int64 (utime .. measurements), 3 floats, then int64 cells,
memory_bytes, delta_seq, keyframes_sent, filter_checksum; driver_status_t starts utime, string source, model,
return_mode, 3 floats, then int64 counters."""
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from lcm_log_check import events  # noqa: E402  (the log reader record.sh checks with)

MAPPER = ["utime", "scans_in", "scans_dropped_behind", "scans_dropped_no_pose", "scans_late", "scans_rejected",
          "poses_in", "poses_rejected", "scans_mapped", "measurements"]
DRIVER = ["data_packets", "position_packets", "packets_lost", "bad_size", "bad_block_flag", "foreign_sender",
          "bad_other", "scans_published", "publish_errors"]


def mapper_status(b):
    v = dict(zip(MAPPER, struct.unpack_from(">10q", b, 8)))
    cells, _, delta_seq, _, checksum = struct.unpack_from(">5q", b, 8 + 80 + 12)
    v.update(cells=cells, delta_seq=delta_seq, filter_checksum=f"{checksum & 0xFFFFFFFFFFFFFFFF:016x}")
    return v


def driver_status(b):
    (n,) = struct.unpack_from(">i", b, 16)
    at = 20 + n + 2 + 12
    return dict(zip(DRIVER, struct.unpack_from(">9q", b, at)))


last = {}
for channel, _, payload in events(sys.argv[1]):
    if channel == "OGF_MAPPER_STATUS":
        last["mapper"] = mapper_status(payload)
    elif channel.startswith("VELODYNE_STATUS"):  # VELODYNE_STATUS_R2: driver_R2
        last["driver" + channel[len("VELODYNE_STATUS"):]] = driver_status(payload)
for who, values in sorted(last.items()):
    for key, value in values.items():
        print(f"{who}.{key} {value}")
