"""ogf.MapClient follows a real ogf-mapper over udpm on loopback (fed by ogf-driver and ogf-replay, as the
main job does) to the mapper's checksum; its cells agree with the mapper's final snapshot and its answers to
ogf-map-query agree with ogf.Map's queries of that snapshot. ogf.NavClient follows a real OGF_NAV_GRID
publisher (nav_test_publisher.cpp, navigation::NavStream) to the published checksum and grid."""

import os
import re
import signal
import socket
import subprocess
import time

import numpy as np
import pytest

import ogf
from conftest import TEST_BIN_DIR, program, run


def start(args, log):
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, text=True)


def stop(process, timeout=60):
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
        try:
            return process.wait(timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    return process.returncode


def wait_for_line(path, pattern, timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if re.search(pattern, path.read_text(errors="replace"), re.M):
            return
        time.sleep(0.1)
    pytest.fail(f"'{pattern}' never appeared in {path}:\n{path.read_text(errors='replace')}")


def test_bad_lcm_url_raises_value_error():
    with pytest.raises(ValueError, match="nosuchprovider://x"):
        ogf.MapClient("nosuchprovider://x")
    with pytest.raises(ValueError, match="nosuchprovider://x"):
        ogf.NavClient(lcm_url="nosuchprovider://x")


def test_a_bus_port_held_unshared_raises_value_error(loopback_bus):
    url = loopback_bus(20)
    port = int(re.search(r":(\d+)\?", url).group(1))
    # A plain UDP socket on the port, as the kernel binds every sending socket: udpm cannot bind it too.
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as held:
        held.bind(("0.0.0.0", port))
        with pytest.raises(ValueError, match="cannot receive on the LCM bus"):
            ogf.MapClient(url)
        with pytest.raises(ValueError, match="cannot receive on the LCM bus"):
            ogf.NavClient(lcm_url=url)


def test_map_client_follows_a_real_mapper_to_its_checksum(sim_lab, loopback_bus, tmp_path):
    url = loopback_bus(1)
    data_port = 30000 + os.getpid() % 10000
    logs = {name: open(tmp_path / f"{name}.log", "w") for name in ("mapper", "driver", "replay")}
    state = tmp_path / "state"
    mapper = start([program("ogf-mapper"), "--lcm-url", url, "--state-dir", str(state), "--config",
                    str(sim_lab / "mapper.yaml")], logs["mapper"])
    driver = None
    try:
        wait_for_line(tmp_path / "mapper.log", r"mapping ", 30)
        driver = start([program("ogf-driver"), "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port",
                        str(data_port), "--position-port", str(data_port + 1)], logs["driver"])
        client = ogf.MapClient(url)
        assert client.lcm_url.startswith(url.split("?")[0]) and client.channel == "OGF_MAP_DELTA"
        replay = start([program("ogf-replay"), "--pcap", str(sim_lab / "sim" / "capture.pcap"), "--dest",
                        "127.0.0.1", "--data-port", str(data_port), "--position-port", str(data_port + 1),
                        "--speed", "2", "--odometry", str(sim_lab / "sim" / "odometry.csv"), "--lcm-url", url,
                        "--start-delay", "1.0"], logs["replay"])
        while replay.poll() is None:
            client.poll(0.5)
        assert replay.returncode == 0, (tmp_path / "replay.log").read_text()
        stop(driver)
        # Until the mapper has drained its queue: the sequence stands still for 3 s.
        last, still = None, 0
        for _ in range(120):
            client.poll(1.0)
            still = still + 1 if client.seq == last else 0
            last = client.seq
            if still >= 3:
                break
        assert client.wait_consistent(10.0), f"seq {client.seq} gaps {client.gaps}"
        assert client.consistent and client.checksum == client.server_checksum
        assert client.seq > 0 and client.keyframes >= 1 and client.malformed == 0
        assert len(client) > 1000 and client.keys.shape == (len(client), 3)
        keys, cls, p = client.keys.copy(), client.cell_class.copy(), client.probability.copy()

        # ogf-map-query asks the running mapper; the same points asked of its final snapshot below.
        occupied = keys[cls == 1][:: max(1, int((cls == 1).sum()) // 8)][:8]
        points = (occupied + 0.5) * client.resolution
        answer = run([program("ogf-map-query"), "--lcm-url", url, "cell"] + [f"{v:.3f}" for v in points.ravel()])
    finally:
        if driver is not None:
            stop(driver)
        rc = stop(mapper)
        for f in logs.values():
            f.close()
    assert rc == 0, (tmp_path / "mapper.log").read_text()

    snapshot = ogf.load_map(state / "snapshot.ogfs")
    assert snapshot.kind == "snapshot" and snapshot.seq >= 0
    # Every published cell is a cell of the mapper's map, of the class the mapper gives it, its probability
    # within the deltas' quantisation and publishing step (deltas.probability_step 0.02).
    index = {tuple(k): i for i, k in enumerate(snapshot.keys.tolist())}
    rows = np.array([index[tuple(k)] for k in keys.tolist()])
    np.testing.assert_array_equal(snapshot.cell_class[rows], cls)
    assert np.max(np.abs(snapshot.probability[rows] - p)) <= 0.02 + 1e-3

    lines = [l.split() for l in answer.splitlines() if re.match(r"^\s*-?\d", l)]
    assert len(lines) == len(points)
    for (x, y, z, prob, klass, mean, variance, entropy), point in zip(lines, points):
        q = snapshot.query(*point)
        assert float(prob) == pytest.approx(q["probability"], abs=1e-4)
        assert {"occ": 1, "free": -1, "unk": 0}[klass] == q["cell_class"]
        assert float(mean) == pytest.approx(q["mean"], abs=1e-4)
        assert float(variance) == pytest.approx(q["variance"], abs=1e-4)


def follow_nav_publisher(client, url, source, seconds, batches):
    """Runs ogf_test_nav_publisher on `source` (a map file or "far-apart") until `client` is consistent at
    its last update; returns the match of its line (seq, checksum, known columns, width, height)."""
    publisher = subprocess.Popen([str(TEST_BIN_DIR / "ogf_test_nav_publisher"), url, source, seconds, batches],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = publisher.stdout.readline()
        m = re.match(r"published seq (\d+) checksum ([0-9a-f]+) known_columns (\d+) width (\d+) height (\d+)", line)
        assert m, f"publisher said: {line!r} {publisher.stderr.read() if publisher.poll() is not None else ''}"
        seq = int(m.group(1))
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline and not (client.consistent and client.seq == seq):
            client.wait_consistent(1.0)
        assert client.consistent and client.seq == seq, f"seq {client.seq} of {seq}, gaps {client.gaps}"
    finally:
        stop(publisher)
    return m


def test_nav_client_follows_a_nav_grid_publisher_to_its_checksum(lab_map, loopback_bus, tmp_path):
    url = loopback_bus(2)
    client = ogf.NavClient(url)
    assert client.needs_keyframe and client.seq == -1 and client.grid().width == 0
    m = follow_nav_publisher(client, url, str(lab_map["map"]), "30", "5")
    checksum, known = int(m.group(2), 16), int(m.group(3))
    assert client.checksum == checksum == client.server_checksum
    assert client.known_columns == known > 100
    grid = client.grid()
    expected = ogf.load_map(lab_map["map"]).project()
    assert grid.checksum == expected.checksum == checksum
    assert (grid.origin_key, grid.width, grid.height) == (expected.origin_key, expected.width, expected.height)
    np.testing.assert_array_equal(grid.cost, expected.cost)
    np.testing.assert_array_equal(grid.column_class, expected.column_class)
    assert grid.resolution == expected.resolution and grid.max_height == expected.max_height


def test_nav_client_refuses_a_dense_grid_of_columns_too_far_apart(loopback_bus):
    """Two known columns 2 000 000 columns apart (as a forged or damaged stream can place them): the client
    follows them, and grid() raises ValueError saying how far they spread and the limit (2^24 columns unless
    max_columns asks for more, up to 2^28) instead of allocating the rectangle (8 * 10^8 columns)."""
    url = loopback_bus(4)
    client = ogf.NavClient(url)
    m = follow_nav_publisher(client, url, "far-apart", "20", "1")
    assert (m.group(4), m.group(5)) == ("0", "0")  # no dense grid on the publisher's side either
    assert client.known_columns == 2
    with pytest.raises(ValueError, match=r"span 2000001 × 401 columns, more than the dense grid's limit of 16777216"):
        client.grid()
    with pytest.raises(ValueError, match=r"limit of 268435456"):
        client.grid(max_columns=2**28)
    with pytest.raises(ValueError, match=r"max_columns must be from 1 to 2\^28"):
        client.grid(max_columns=2**29)
    assert client.dropped == 0 and client.malformed == 0
