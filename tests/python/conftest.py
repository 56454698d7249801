"""Shared fixtures of the Python package's tests: where the build's programs are, a loopback udpm bus,
and a map of the simulated lab made by the project's own programs (ogf-sim, then ogf-map).

The ctest entry (tests/python/CMakeLists.txt) sets PYTHONPATH to build/python, OGF_BIN_DIR to build/bin,
OGF_TEST_BIN_DIR to build/tests and OGF_SOURCE_DIR to the checkout.
"""

import csv
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("OGF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN_DIR = pathlib.Path(os.environ.get("OGF_BIN_DIR", SOURCE_DIR / "build" / "bin"))
TEST_BIN_DIR = pathlib.Path(os.environ.get("OGF_TEST_BIN_DIR", SOURCE_DIR / "build" / "tests"))
SHARED_DIR = pathlib.Path(os.environ.get("OGF_SHARED_DIR", SOURCE_DIR.parent / "shared"))


def program(name):
    """The path of a program of the build (build/bin), failing the test when it was not built."""
    path = BIN_DIR / name
    assert path.is_file(), f"{path} is missing: build the project first (scripts/build.sh)"
    return str(path)


def run(args, **kwargs):
    """Runs a program to completion, failing with its output when it exits non-zero."""
    done = subprocess.run(args, capture_output=True, text=True, timeout=600, **kwargs)
    assert done.returncode == 0, f"{' '.join(map(str, args))} exited {done.returncode}:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def sim_extrinsic(sim_dir):
    """The sensor's mount ogf-sim wrote into sim.yaml, as the mapper's map.extrinsic (scripts/run-common.sh)."""
    text = (pathlib.Path(sim_dir) / "sim.yaml").read_text()
    m = re.search(r"^sensor_to_body: \{xyz: (\[[^]]*\]), quaternion_wxyz: (\[[^]]*\])\}", text, re.M)
    assert m, f"no sensor_to_body in {sim_dir}/sim.yaml"
    return f"{{translation: {m.group(1)}, quaternion: {m.group(2)}}}"


def read_cell_csv(path):
    """The rows of `ogf-map --export-csv` (x,y,z,p,class,variance) as numpy arrays."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["x", "y", "z", "p", "class", "variance"], rows[0]
    data = np.array(rows[1:], dtype=np.float64).reshape(-1, 6)
    return {"centres": data[:, 0:3], "p": data[:, 3], "cls": data[:, 4].astype(np.int8), "variance": data[:, 5]}


@pytest.fixture(scope="session")
def sim_lab(tmp_path_factory):
    """A 6 s drive through the simulated lab (ogf-sim): capture.pcap, odometry.csv, sim.yaml, and the mapper
    configuration with the sensor's mount (mapper.yaml)."""
    root = tmp_path_factory.mktemp("lab")
    run([program("ogf-sim"), "--world", "lab", "--duration", "6", "--out", str(root / "sim"), "--log-level", "warn"])
    (root / "mapper.yaml").write_text(f"map:\n  extrinsic: {sim_extrinsic(root / 'sim')}\n")
    return root


@pytest.fixture(scope="session")
def lab_map(sim_lab):
    """The lab mapped offline by ogf-map: the map file and its cell CSV."""
    out = sim_lab / "offline"
    out.mkdir()
    run([program("ogf-map"), "--pcap", str(sim_lab / "sim" / "capture.pcap"), "--odometry",
         str(sim_lab / "sim" / "odometry.csv"), "--config", str(sim_lab / "mapper.yaml"), "--out",
         str(out / "map.ogfm"), "--export-csv", str(out / "cells.csv"), "--log-level", "warn"])
    return {"map": out / "map.ogfm", "csv": out / "cells.csv"}


def _routes_over_lo():
    done = subprocess.run(["ip", "route", "get", "239.255.76.67"], capture_output=True, text=True)
    return " dev lo" in done.stdout


@pytest.fixture(scope="session")
def loopback_bus():
    """A function slot -> udpm URL on loopback (ttl=0, a port of this process), after making sure multicast
    routes over lo (adding the route when root, as tests/support/multicast.cpp does); skips otherwise."""
    if not _routes_over_lo():
        if os.geteuid() != 0:
            pytest.skip("no multicast route over lo and not root to add one "
                        "(run: ip link set lo multicast on; ip route add 224.0.0.0/4 dev lo)")
        subprocess.run(["ip", "link", "set", "lo", "multicast", "on"], capture_output=True)
        subprocess.run(["ip", "route", "replace", "224.0.0.0/4", "dev", "lo"], capture_output=True)
        if not _routes_over_lo():
            pytest.skip("could not add a multicast route over lo")

    # As tests/support/multicast.cpp: 256 ports per process, below the kernel's ephemeral ports (every LCM
    # process's send socket holds one of those without sharing it); the upper half for the Python tests.
    try:
        with open("/proc/sys/net/ipv4/ip_local_port_range") as f:
            ephemeral = int(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        ephemeral = 32768
    processes = max(1, (ephemeral - 20000) // 256)

    def url(slot):
        port = 20000 + (os.getpid() % processes) * 256 + 128 + (slot & 127)
        return f"udpm://239.255.76.67:{port}?ttl=0&recv_buf_size=8388608"

    return url
