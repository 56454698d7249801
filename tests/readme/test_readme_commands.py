#!/usr/bin/env python3
"""Runs the README's commands as a new user would, and checks what each promises.

  test_readme_commands.py --source DIR --build DIR --shared DIR [--only NAME ...]

Covered: the quick start's main job, the headline map command under the picture, and "On a robot in five
minutes" (the daemons, the configuration file, recording and replaying the bus, mapping the recording
offline). The blocks are read from README.md by their markers (readme_blocks.py) and run as written, in a
scratch folder that holds `build/` and `scripts/` of the checkout, with $HOME and $LCM_DEFAULT_URL of its
own. The only changes to a command are the ones a test host forces, each listed in SUBSTITUTIONS: the
real sensor is replaced by its capture replayed onto loopback UDP with ogf-replay, and the robot's
odometry by poses of a sensor standing still, published by the same replay on the clock the driver
stamps the packets with. Exit 0 when every check passes; the last line reads "N passed, N failed".
"""

import argparse
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import png_pixels  # noqa: E402
import readme_blocks  # noqa: E402

COVERED_SECTIONS = {"Quick start", "On a robot in five minutes"}
EXPECTED_BLOCKS = {"quick-start", "headline-map", "robot-daemons", "robot-config", "package", "record",
                   "replay", "replay-offline"}
REAL_CAPTURE = "data/real/vlp-16-test-90deg-1-50-frames.pcap"
REAL_CALIBRATION = "data/real/calib/VLP-16.xml"
OCCUPIED_RGB = (25, 25, 25)  # tools/lib/map_io/src/topdown_png.cpp, kOccupied
# The sensor the README addresses is not on a test host: its capture comes from loopback.
SUBSTITUTIONS = [("--sensor-ip 192.168.1.201", "--sensor-ip 127.0.0.1")]

# The real capture's walls seen from above at 0.1 m: the walls' band (z -0.5 to 1.3 m above the sensor)
# draws about 19 000 occupied pixels; a band that misses the walls draws a few hundred (the legend's).
MIN_WALL_PIXELS_REAL = 8000
# The simulated lab at 0.2 m (run.sh's figure): its walls and furniture draw about 118 000 pixels.
MIN_WALL_PIXELS_LAB = 40000
FREE_RGB = (255, 255, 255)


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


class Context:
    def __init__(self, args):
        self.source = os.path.abspath(args.source)
        self.build = os.path.abspath(args.build)
        self.shared = os.path.abspath(args.shared)
        with open(os.path.join(self.source, "README.md"), encoding="utf-8") as f:
            self.blocks, self.problems = readme_blocks.parse(f.read(), COVERED_SECTIONS)
        self.bin = os.path.join(self.build, "bin")

    def shared_file(self, relative):
        path = os.path.join(self.shared, relative)
        return path if os.path.exists(path) else None

    def scratch(self, name):
        """A folder that looks like the checkout to the README's commands (build/, scripts/), with a
        home and an LCM bus of its own."""
        root = tempfile.mkdtemp(prefix=f"ogf-readme-{name}-")
        os.symlink(self.build, os.path.join(root, "build"))
        os.symlink(os.path.join(self.source, "scripts"), os.path.join(root, "scripts"))
        os.makedirs(os.path.join(root, "home"))
        return root

    def env(self, root, port):
        e = dict(os.environ)
        e["HOME"] = os.path.join(root, "home")
        e["LCM_DEFAULT_URL"] = f"udpm://239.255.76.67:{port}?ttl=0"
        e["PATH"] = self.bin + os.pathsep + e.get("PATH", "")
        e.pop("DISPLAY", None)
        return e


def substitute(command):
    for old, new in SUBSTITUTIONS:
        command = command.replace(old, new)
    return command


def run(command, cwd, env, timeout, log):
    """Runs one shell command to its end; returns (exit code, output)."""
    with open(log, "w") as out:
        p = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT,
                           timeout=timeout)
    with open(log) as f:
        return p.returncode, f.read()


def start(command, cwd, env, log):
    out = open(log, "w")
    return subprocess.Popen(["bash", "-c", "exec " + command], cwd=cwd, env=env, stdout=out,
                            stderr=subprocess.STDOUT, start_new_session=True)


def stop(process, sig=signal.SIGTERM, timeout=60):
    if process.poll() is None:
        os.killpg(process.pid, sig)
    try:
        return process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        raise Failure(f"'{' '.join(process.args)}' did not stop within {timeout} s of signal {sig}")


def wait_for(path, pattern, timeout):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if os.path.exists(path):
            with open(path, errors="replace") as f:
                m = re.search(pattern, f.read(), re.M)
            if m:
                return m
        time.sleep(0.2)
    with open(path, errors="replace") as f:
        tail = f.read()[-2000:]
    raise Failure(f"{path}: no line matching '{pattern}' within {timeout} s; it ends:\n{tail}")


def mapper_summary(log):
    """(scans in, scans mapped, filter checksum) from ogf-mapper's last 'stopping:' line."""
    with open(log, errors="replace") as f:
        text = f.read()
    m = re.findall(r"stopping: (\d+) scans in, (\d+) mapped.*?filter checksum ([0-9a-f]{16})", text)
    check(m, f"{log}: no 'stopping: ... filter checksum' line; it ends:\n{text[-2000:]}")
    scans_in, mapped, checksum = m[-1]
    return int(scans_in), int(mapped), checksum


def wall_pixels(png):
    """The occupied pixels of a top-down occupancy picture. A band that holds the floor or a ceiling paints
    nearly every column occupied: the free columns must outnumber the occupied ones."""
    check(os.path.isfile(png), f"{png} was not written")
    occupied, free = png_pixels.count_colour(png, OCCUPIED_RGB), png_pixels.count_colour(png, FREE_RGB)
    check(free > occupied, f"{png}: {occupied} occupied pixels and only {free} free: the band holds a floor "
          "or a ceiling, not walls")
    return occupied


def pcap_span_us(path):
    """First and last record time of a classic pcap file, microseconds."""
    with open(path, "rb") as f:
        header = f.read(24)
        magic = struct.unpack("<I", header[:4])[0]
        endian, nano = {0xA1B2C3D4: ("<", False), 0xA1B23C4D: ("<", True), 0xD4C3B2A1: (">", False),
                        0x4D3CB2A1: (">", True)}[magic]
        first = last = None
        while True:
            rec = f.read(16)
            if len(rec) < 16:
                break
            sec, frac, incl, _ = struct.unpack(endian + "IIII", rec)
            t = sec * 1_000_000 + (frac // 1000 if nano else frac)
            first = t if first is None else first
            last = t
            f.seek(incl, 1)
    return first, last


def write_standstill_odometry(pcap, path):
    """A sensor standing still: the body at the origin every 10 ms across the capture, on its clock."""
    first, last = pcap_span_us(pcap)
    with open(path, "w") as f:
        f.write("utime,x,y,z,qw,qx,qy,qz\n")
        for t in range(first - 1_000_000, last + 2_000_000, 10_000):
            f.write(f"{t},0,0,0,1,0,0,0\n")


# ---- the checks, one per part of the README ------------------------------------------------------------

def test_markers(ctx):
    check(not ctx.problems, "\n".join(ctx.problems))
    missing = EXPECTED_BLOCKS - set(ctx.blocks)
    check(not missing, f"README.md has no marker for {sorted(missing)}: the test cannot find those commands")
    unknown = set(ctx.blocks) - EXPECTED_BLOCKS
    check(not unknown, f"README.md marks {sorted(unknown)}, which this test does not know how to run")


def test_headline_map(ctx):
    """The command under the README's picture draws the walls of the real capture."""
    pcap, calib = ctx.shared_file(REAL_CAPTURE), ctx.shared_file(REAL_CALIBRATION)
    if not pcap or not calib:
        return f"skipped: {os.path.join(ctx.shared, REAL_CAPTURE)} absent (tests read ../shared)"
    command = ctx.blocks["headline-map"].text
    check(command.startswith("ogf-map "), f"the headline command is '{command}'")
    check("FILE" in command and "VLP-16.xml" in command, f"the headline command names no FILE and VLP-16.xml: "
          f"'{command}'")
    root = ctx.scratch("headline")
    command = command.replace("FILE", pcap).replace("VLP-16.xml", calib)
    rc, out = run(command, root, ctx.env(root, 7691), 600, os.path.join(root, "headline.log"))
    check(rc == 0, f"'{command}' exited {rc}:\n{out[-3000:]}")
    band = re.search(r"z (-?[0-9.]+) to (-?[0-9.]+) m", out)
    check(band, f"the command did not say which height band it drew:\n{out[-2000:]}")
    walls = wall_pixels(os.path.join(root, "png", "occupancy.png"))
    check(walls >= MIN_WALL_PIXELS_REAL,
          f"png/occupancy.png has {walls} occupied pixels (at least {MIN_WALL_PIXELS_REAL} show the walls); "
          f"band z {band.group(1)} to {band.group(2)} m")
    shutil.rmtree(root, ignore_errors=True)
    return f"{walls} wall pixels, band z {band.group(1)} to {band.group(2)} m"


def test_quick_start(ctx):
    """scripts/run.sh as written: maps every scan, the client agrees, the picture shows the lab's walls.
    scripts/test.sh is not run here: it is what runs this test."""
    lines = readme_blocks.commands(ctx.blocks["quick-start"].text)
    check(lines[:2] == ["scripts/run.sh", "scripts/test.sh"], f"the quick start's commands are {lines}")
    env = dict(os.environ)
    env["OGF_BUILD_DIR"] = ctx.build
    log = os.path.join(ctx.build, "readme-run.log")
    rc, out = run(lines[0], ctx.source, env, 900, log)
    check(rc == 0, f"scripts/run.sh exited {rc} (log {log}):\n{out[-3000:]}")
    outdir = os.path.join(ctx.source, "out")
    scans_in, mapped, _ = mapper_summary(os.path.join(outdir, "logs", "mapper.log"))
    # A busy machine may make the mapper fall behind and drop scans; each is counted, none is lost unsaid.
    with open(os.path.join(outdir, "logs", "mapper.log"), errors="replace") as f:
        stopping = re.findall(r"stopping: (\d+) scans in, (\d+) mapped, (\d+) dropped behind, (\d+) without poses",
                              f.read())
    check(stopping, "the main job's mapper logged no 'stopping:' counts")
    counted = [int(v) for v in stopping[-1]]
    check(counted[0] == sum(counted[1:]), f"the main job's mapper counts do not add up: {stopping[-1]}")
    check(mapped > 150 and counted[3] == 0,
          f"the main job's mapper mapped {mapped} of {scans_in} scans, {counted[3]} without poses")
    with open(os.path.join(outdir, "map-client.txt")) as f:
        client = f.read()
    check(re.search(r"\bconsistent yes\b", client), f"the map client did not end consistent with the mapper: {client}")
    check(re.search(r"\bnav_consistent yes\b", client),
          f"the map client did not end with the mapper's navigation grid: {client}")
    for name in ["map.ogfs", "map_occupied.ply", "map.bt", "octomap.bt", "nav/map.pgm", "nav/map.yaml", "accuracy.txt"]:
        path = os.path.join(outdir, name)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"out/{name} is missing or empty")
    last = out.rstrip("\n").splitlines()[-1]
    check(last == f"outputs:    {outdir}", f"scripts/run.sh's last line is '{last}', not one naming {outdir}")
    # Every picture covers the truth's grid: they line up when a person flips between them.
    sizes = {}
    for name in sorted(os.listdir(os.path.join(outdir, "png"))):
        width, height, _ = png_pixels.read_rgb(os.path.join(outdir, "png", name))
        sizes[name] = (width, height)
    check({"truth.png", "ogf_errors.png", "octomap_errors.png", "occupancy.png", "entropy.png"} <= set(sizes),
          f"out/png holds {sorted(sizes)}")
    check(len(set(sizes.values())) == 1, f"the pictures of out/png differ in size: {sizes}")
    with open(os.path.join(outdir, "logs", "mapper.log")) as f:
        mapper_log = f.read()
    check("but no pose on" not in mapper_log,
          "the mapper warns of missing poses although the replay stopped scans and poses together")
    walls = wall_pixels(os.path.join(outdir, "png", "occupancy.png"))
    check(walls >= MIN_WALL_PIXELS_LAB, f"out/png/occupancy.png has {walls} occupied pixels "
          f"(at least {MIN_WALL_PIXELS_LAB} show the lab's walls)")
    return f"{mapped} of {scans_in} scans mapped, {walls} wall pixels"


def test_robot(ctx):
    """"On a robot in five minutes": the driver and the mapper as written, fed by the real capture and a
    standing-still odometry; the bus recorded with record.sh, replayed by the README's recipe into a second
    mapper and mapped offline, all three maps the same."""
    pcap = ctx.shared_file(REAL_CAPTURE)
    if not pcap:
        return f"skipped: {os.path.join(ctx.shared, REAL_CAPTURE)} absent (tests read ../shared)"
    root = ctx.scratch("robot")
    env = ctx.env(root, 7692)
    logs = os.path.join(root, "logs")
    os.makedirs(logs)
    with open(os.path.join(root, "my-mapper.yaml"), "w") as f:
        f.write(ctx.blocks["robot-config"].text + "\n")
    write_standstill_odometry(pcap, os.path.join(root, "standstill.csv"))

    daemons = readme_blocks.commands(ctx.blocks["robot-daemons"].text)
    check(len(daemons) == 2 and "ogf-driver" in daemons[0] and "ogf-mapper" in daemons[1],
          f"step 2's commands are {daemons}")
    record_lines = readme_blocks.commands(ctx.blocks["record"].text)
    check(len(record_lines) == 1 and record_lines[0].startswith("scripts/record.sh"),
          f"step 4's record command is {record_lines}")
    # The synopsis' optional parts in [...] are left out: the plainest call, as a user would type it.
    record = re.sub(r"\s*\[[^]]*\]", "", record_lines[0])
    running = []
    try:
        recorder = start(record, root, env, os.path.join(logs, "record.log"))
        running.append(recorder)
        wait_for(os.path.join(logs, "record.log"), r"recording", 30)
        mapper = start(substitute(daemons[1]), root, env, os.path.join(logs, "mapper.log"))
        running.append(mapper)
        driver = start(substitute(daemons[0]), root, env, os.path.join(logs, "driver.log"))
        running.append(driver)
        wait_for(os.path.join(logs, "mapper.log"), r"mapping .* on ", 30)
        # The sensor and the robot: the capture onto the driver's port, the odometry onto POSE, both on
        # the clock the driver stamps the packets with.
        rc, out = run(f"{ctx.bin}/ogf-replay --pcap {pcap} --dest 127.0.0.1 --odometry standstill.csv "
                      f"--odometry-clock auto --start-delay 1", root, env, 300, os.path.join(logs, "replay.log"))
        check(rc == 0, f"ogf-replay exited {rc}:\n{out[-2000:]}")
        time.sleep(1.0)
        check(stop(driver, signal.SIGINT) == 0, "ogf-driver did not exit 0 on Ctrl-C")
        time.sleep(2.0)
        check(stop(mapper, signal.SIGINT) == 0, "ogf-mapper did not exit 0 on Ctrl-C")
        recorded = stop(recorder, signal.SIGINT)
        running.clear()
        with open(os.path.join(logs, "record.log"), errors="replace") as f:
            record_out = f.read()
        check(recorded == 0, f"record.sh exited {recorded} after Ctrl-C:\n{record_out[-2000:]}")
    finally:
        for p in running:
            stop(p, signal.SIGKILL)
    live_in, live_mapped, live_sum = mapper_summary(os.path.join(logs, "mapper.log"))
    # On a busy machine the live mapper may fall behind and drop a scan (counted): what it mapped is compared
    # below only when it is every recorded scan.
    check(live_mapped >= 45, f"the live mapper mapped {live_mapped} of {live_in} scans of the 50-revolution capture")
    check(os.path.isdir(os.path.join(env["HOME"], "ogf-map")), "the mapper left no state in ~/ogf-map")

    # Replay the recording by the README's recipe into a mapper of its own.
    replay = ctx.blocks["replay"].text
    replay_log = os.path.join(logs, "replay-mapper.log")
    rc, out = run(replay, root, env, 300, replay_log)
    check(rc == 0, f"the replay recipe exited {rc}:\n{out[-3000:]}")
    _, re_mapped, re_sum = mapper_summary(replay_log)

    # And offline, as fast as the machine allows: every scan of the recording, the reference.
    offline = substitute(ctx.blocks["replay-offline"].text)
    rc, out = run(offline, root, env, 300, os.path.join(logs, "offline.log"))
    check(rc == 0, f"'{offline}' exited {rc}:\n{out[-3000:]}")
    m = re.search(r"^scans (\d+) .* checksum ([0-9a-f]{16})", out, re.M)
    check(m, f"'{offline}' printed no summary line:\n{out[-2000:]}")
    recorded, offline_sum = int(m.group(1)), m.group(2)
    # A mapper that received every recorded scan has the offline map, bit for bit. UDP on a busy machine may
    # lose a scan before a mapper receives it (the receive buffer overflows while the reader is not
    # scheduled); such a mapper is compared on what it received, never on speed.
    notes = []
    for name, received, checksum in [("live", live_mapped, live_sum), ("replayed", re_mapped, re_sum)]:
        check(received <= recorded, f"the {name} mapper mapped {received} scans, the recording holds {recorded}")
        check(received >= 45, f"the {name} mapper mapped only {received} of {recorded} recorded scans")
        if received == recorded:
            check(checksum == offline_sum,
                  f"the {name} map's filter checksum {checksum} differs from the offline map's {offline_sum} "
                  f"of the same {recorded} scans")
        else:
            notes.append(f"{name}: {recorded - received} of {recorded} scans lost or dropped behind, not compared")
    shutil.rmtree(root, ignore_errors=True)
    return (f"{live_mapped} of {live_in} scans live, {re_mapped} replayed, {recorded} offline; checksum "
            f"{offline_sum}" + ("; " + "; ".join(notes) if notes else ""))


CHECKS = [("markers", test_markers), ("headline-map", test_headline_map), ("robot", test_robot),
          ("quick-start", test_quick_start)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("--shared", required=True)
    parser.add_argument("--only", action="append", help="run only these checks")
    args = parser.parse_args()
    ctx = Context(args)
    for name in ctx.blocks:
        if ctx.blocks[name].skip_reason:
            print(f"README block '{name}' (README.md:{ctx.blocks[name].line}) not run: "
                  f"{ctx.blocks[name].skip_reason}")
    passed = failed = 0
    for name, fn in CHECKS:
        if args.only and name not in args.only:
            continue
        if ctx.problems and name != "markers":
            print(f"[SKIP] {name}: not run, the README's markers are wrong", flush=True)
            continue
        began = time.time()
        try:
            said = fn(ctx)
            print(f"[ OK ] {name} ({time.time() - began:.0f} s){': ' + said if said else ''}", flush=True)
            passed += 1
        except Failure as e:
            print(f"[FAIL] {name}: {e}", flush=True)
            failed += 1
        except Exception:  # a defect of the test itself is a failure too, with its trace
            print(f"[FAIL] {name}:\n{traceback.format_exc()}", flush=True)
            failed += 1
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
