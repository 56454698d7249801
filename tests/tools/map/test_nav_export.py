#!/usr/bin/env python3
"""ogf-map --export-nav read back by readers ogf did not write.

Pillow decodes map.pgm and PyYAML map.yaml; the loading rules are those the ROS map_server documentation
states ("Map format"): with negate 0 a pixel x reads p = (255 - x) / 255; p > occupied_thresh is occupied,
p < free_thresh free; in between, trinary mode reads unknown and scale mode, as nav2_map_server does,
rint(100 (p - free_thresh) / (occupied_thresh - free_thresh)); the image's last row is the map's bottom and
`origin` is the pose of the lower-left pixel. The grid read that way must equal, column for column, the projection of
the map's CSV export computed here from the rule of mapper/navigation (any occupied cell in the band makes a
column occupied; half of its layers free make it free), and the simulated lab's pillar, walls and the robot's
path must be where the world puts them.

Usage: test_nav_export.py --bin BUILD/bin
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

try:
    import yaml
    from PIL import Image
except ImportError as e:  # the Debian packages python3-yaml and python3-pil (scripts/install-deps.sh)
    print(f"test_nav_export: needs PyYAML and Pillow for the system python: {e}", file=sys.stderr)
    sys.exit(1)

RES = 0.2
FLOOR, MIN_H, MAX_H, FREE_FRACTION = 0.0, 0.25, 1.5, 0.5  # the nav.* defaults


def run(*args: str) -> str:
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(args)} failed ({done.returncode}):\n{done.stdout}\n{done.stderr}")
    return done.stdout + done.stderr


def load_map_server(yaml_path: str) -> tuple[dict, dict[tuple[int, int], int]]:
    """The map as map_server loads it: {(column, row from the bottom): -1 | 0..100}."""
    meta = yaml.safe_load(open(yaml_path))
    image = Image.open(os.path.join(os.path.dirname(yaml_path), meta["image"]))
    assert image.mode == "L", image.mode
    width, height = image.size
    pixels = image.load()
    occ_t, free_t = float(meta["occupied_thresh"]), float(meta["free_thresh"])
    mode = meta.get("mode", "trinary")
    out = {}
    for row in range(height):
        for col in range(width):
            x = pixels[col, row]
            p = x / 255.0 if meta["negate"] else (255 - x) / 255.0
            if p > occ_t:
                v = 100
            elif p < free_t:
                v = 0
            elif mode == "trinary":
                v = -1
            else:
                v = round(100 * (p - free_t) / (occ_t - free_t))
            out[(col, height - 1 - row)] = v
    return meta, out


def layers() -> tuple[int, int]:
    lo = math.ceil((FLOOR + MIN_H) / RES - 0.5 - 1e-9)
    hi = math.floor((FLOOR + MAX_H) / RES - 0.5 + 1e-9)
    return lo, hi


def cell_cost(p: float, variance: float) -> int:
    p = min(max(p, 1e-4), 1 - 1e-4)
    s = max(variance, 0.0)
    n = statistics.NormalDist()
    return round(100 * n.cdf(n.inv_cdf(p) * math.sqrt(1 + s) + math.sqrt(s)))


def project_csv(path: str) -> dict[tuple[int, int], tuple[int, int]]:
    """{column key: (class -1/0/1, cost)} of the known columns, from the CSV export."""
    lo, hi = layers()
    need = max(1, math.ceil(FREE_FRACTION * (hi - lo + 1) - 1e-9))
    columns: dict[tuple[int, int], list[tuple[int, int]]] = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            k = [math.floor(float(r[a]) / RES) for a in "xyz"]
            if lo <= k[2] <= hi:
                columns.setdefault((k[0], k[1]), []).append(
                    (int(r["class"]), cell_cost(float(r["p"]), float(r["variance"]))))
    known = {}
    for key, cells in columns.items():
        cost = max(c for _, c in cells)
        if any(c == 1 for c, _ in cells):
            known[key] = (1, cost)
        elif sum(1 for c, _ in cells if c == -1) >= need:
            known[key] = (-1, cost)
    return known


def at(meta: dict, grid: dict, x: float, y: float) -> int:
    col = math.floor((x - meta["origin"][0]) / meta["resolution"] + 1e-9)
    row = math.floor((y - meta["origin"][1]) / meta["resolution"] + 1e-9)
    return grid.get((col, row), -2)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True)
    a = ap.parse_args()
    failures = []

    def check(ok: bool, what: str) -> None:
        print(("ok    " if ok else "FAIL  ") + what)
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as d:
        sim = os.path.join(d, "sim")
        run(f"{a.bin}/ogf-sim", "--world", "lab", "--duration", "10", "--out", sim)
        mount = re.search(r"sensor_to_body: \{xyz: (\[[^]]*\]), quaternion_wxyz: (\[[^]]*\])\}",
                          open(os.path.join(sim, "sim.yaml")).read())
        config = os.path.join(d, "mapper.yaml")
        with open(config, "w") as f:
            f.write(f"map:\n  extrinsic: {{translation: {mount.group(1)}, quaternion: {mount.group(2)}}}\n")
        log = run(f"{a.bin}/ogf-map", "--pcap", f"{sim}/capture.pcap", "--odometry", f"{sim}/odometry.csv",
                  "--config", config, "--out", f"{d}/map.ogfm", "--export-csv", f"{d}/cells.csv",
                  "--export-nav", f"{d}/nav")
        check("map.pgm and map.yaml (trinary)" in log, "ogf-map says what it wrote")
        run(f"{a.bin}/ogf-map", "--from-map", f"{d}/map.ogfm", "--export-nav", f"{d}/scale", "--nav-mode", "scale")

        meta, grid = load_map_server(f"{d}/nav/map.yaml")
        check(meta["image"] == "map.pgm" and meta["mode"] == "trinary", "map.yaml names map.pgm, trinary")
        check(abs(meta["resolution"] - RES) < 1e-12, f"resolution {meta['resolution']}")
        projected = project_csv(f"{d}/cells.csv")
        expected = {}
        for key, (cls, _) in projected.items():
            expected[key] = 100 if cls == 1 else 0
        origin_col = round(meta["origin"][0] / RES)
        origin_row = round(meta["origin"][1] / RES)
        check(origin_col == min(k[0] for k in projected) and origin_row == min(k[1] for k in projected),
              f"origin {meta['origin'][:2]} is the south-west known column")
        loaded = {(c + origin_col, r + origin_row): v for (c, r), v in grid.items() if v != -1}
        mismatched = [k for k in set(loaded) | set(expected) if loaded.get(k) != expected.get(k)]
        check(not mismatched and len(loaded) > 1000,
              f"{len(loaded)} known columns read back equal the CSV's projection ({len(mismatched)} differ: "
              f"{sorted(mismatched)[:5]})")
        # The lab (tools/lib/sim/presets/lab.yaml): a pillar at (5, 4), walls around 10 x 8 m, a loop at y 2.5 and 5.2.
        check(at(meta, grid, 5.0, 4.0) == 100 and at(meta, grid, 5.0, -0.1) == 100, "the pillar and the south wall are occupied")
        check(at(meta, grid, -0.1, 2.0) == 100 and at(meta, grid, 10.1, 2.0) == 100, "the west and east walls are occupied")
        check(all(at(meta, grid, x, 2.5) == 0 for x in (3.0, 4.0, 6.0, 7.0)), "the path along y = 2.5 m is free")
        check(all(at(meta, grid, x, 5.2) == 0 for x in (3.0, 6.5, 7.5)), "the path along y = 5.2 m is free")

        smeta, sgrid = load_map_server(f"{d}/scale/map.yaml")
        check(smeta["mode"] == "scale", "--nav-mode scale writes mode: scale")
        off = [k for k, (cls, cost) in projected.items()
               if abs(sgrid.get((k[0] - origin_col, k[1] - origin_row), -100) - cost) > 1]
        check(not off, f"scale mode reads each known column's cost back within 1 ({len(off)} off: {off[:5]})")
    print(f"{len(failures)} failed" if failures else "all passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
