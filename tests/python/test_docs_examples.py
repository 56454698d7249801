"""The examples of docs/python.md run as written: the code blocks marked `<!-- python-doc-test: NAME -->`
are extracted from the page and run with the build tree's package, the slice plot on a map placed where
scripts/run.sh leaves the main job's map (out/map.ogfs), the live-grid follower against a real OGF_NAV_GRID
publisher on a loopback bus given as LCM_DEFAULT_URL."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

import ogf
from conftest import SOURCE_DIR, TEST_BIN_DIR

MARKER = re.compile(r"^<!-- python-doc-test: ([a-z0-9-]+) -->\s*\n```python\n(.*?)^```", re.M | re.S)


def doc_blocks():
    return dict(MARKER.findall((SOURCE_DIR / "docs" / "python.md").read_text()))


def run_block(code, cwd, env=None, timeout=120):
    """Runs the code as a script in `cwd` with the package under test on its path; its standard output."""
    script = cwd / "example.py"
    script.write_text(code)
    package_root = str(pathlib.Path(ogf.__file__).resolve().parents[1])
    env = dict(env or os.environ, PYTHONPATH=package_root)
    done = subprocess.run([sys.executable, str(script)], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env=env)
    assert done.returncode == 0, f"the example failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def test_the_page_has_both_examples():
    assert set(doc_blocks()) == {"plot-slice", "follow-grid"}


def test_the_page_runs_its_examples_with_debians_python():
    # Debian's numpy and matplotlib are /usr/bin/python3's: a bare `python3` may be another interpreter.
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    commands = re.findall(r"PYTHONPATH=build/python (\S+)", text)
    assert commands, "docs/python.md says nowhere how to run the examples"
    assert all(c.rstrip("`.,;)") == "/usr/bin/python3" for c in commands), commands


def test_plot_slice_example_draws_the_main_jobs_map_to_a_png(lab_map, tmp_path):
    pytest.importorskip("matplotlib", reason="python3-matplotlib is not installed")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "map.ogfs").write_bytes(lab_map["map"].read_bytes())
    out = run_block(doc_blocks()["plot-slice"], tmp_path)
    assert "wrote out/slice.png" in out
    occupied = int(re.search(r"occupied: (\d+)", out).group(1))
    assert occupied > 100
    png = tmp_path / "out" / "slice.png"
    assert not (tmp_path / "slice.png").exists(), "the example writes into the folder it runs in, not out/"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib.image
    pixels = matplotlib.image.imread(str(png))
    assert pixels.shape[0] >= 400 and pixels.shape[1] >= 1000
    # Drawn, not blank: many distinct colours.
    assert len({tuple(p) for p in pixels[::7, ::7].reshape(-1, pixels.shape[2]).tolist()}) > 50


def test_follow_grid_example_prints_the_grid_of_a_live_publisher(lab_map, loopback_bus, tmp_path):
    url = loopback_bus(3)
    publisher = subprocess.Popen([str(TEST_BIN_DIR / "ogf_test_nav_publisher"), url, str(lab_map["map"]), "25", "3"],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = publisher.stdout.readline()
        checksum = re.search(r"checksum ([0-9a-f]+)", line).group(1)
        out = run_block(doc_blocks()["follow-grid"], tmp_path, env=dict(os.environ, LCM_DEFAULT_URL=url))
    finally:
        publisher.terminate()
        publisher.wait(30)
    lines = [l for l in out.splitlines() if l.startswith("seq ")]
    assert lines, out
    assert lines[-1].endswith(f"checksum {checksum}")
    assert re.search(r"\d+ occupied, \d+ free", lines[-1])
