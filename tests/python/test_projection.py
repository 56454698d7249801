"""Map.project(): the 2-D navigation grid agrees with a projection computed here, independently, from the
map's `ogf-map --export-csv` rows with the rule of mapper/navigation/include/ogf/navigation/column_rule.hpp
(class from the band's cell classes; cost 100 * max Phi(Phi^-1(p) * sqrt(1 + s) + sqrt(s)))."""

import math
from collections import defaultdict
from statistics import NormalDist

import numpy as np
import pytest

import ogf
from conftest import read_cell_csv

STD_NORMAL = NormalDist()


def cell_cost(p, s):
    p = min(max(p, 1e-4), 1 - 1e-4)
    s = s if s > 0 else 0.0
    mean = STD_NORMAL.inv_cdf(p) * math.sqrt(1 + s)
    return round(100 * STD_NORMAL.cdf(mean + math.sqrt(s)))


def project_csv(csv, resolution, floor_z, min_height, max_height, min_free_fraction):
    """{(x, y): (cost, class)} of every column with a band cell, from the CSV rows alone."""
    lo = math.ceil((floor_z + min_height) / resolution - 0.5 - 1e-9)
    hi = math.floor((floor_z + max_height) / resolution - 0.5 + 1e-9)
    needed = max(1, math.ceil(min_free_fraction * (hi - lo + 1) - 1e-9))
    keys = np.floor(csv["centres"] / resolution).astype(int)
    columns = defaultdict(list)
    for i in np.flatnonzero((keys[:, 2] >= lo) & (keys[:, 2] <= hi)):
        columns[(keys[i, 0], keys[i, 1])].append((cell_cost(csv["p"][i], csv["variance"][i]), csv["cls"][i]))
    out = {}
    for key, cells in columns.items():
        cost = max(c for c, _ in cells)
        if any(cls == 1 for _, cls in cells):
            out[key] = (cost, 1)
        elif sum(cls == -1 for _, cls in cells) >= needed:
            out[key] = (cost, -1)
        else:
            out[key] = (-1, 0)
    return out


@pytest.fixture(scope="module")
def lab(lab_map):
    return ogf.load_map(lab_map["map"]), read_cell_csv(lab_map["csv"])


@pytest.mark.parametrize("band", [dict(), dict(floor_z=0.0, min_height=0.45, max_height=0.95, min_free_fraction=1.0)],
                         ids=["default band", "narrow band, every layer free"])
def test_projection_agrees_with_an_independent_projection_of_the_csv(lab, band):
    m, csv = lab
    full = dict(floor_z=0.0, min_height=0.25, max_height=1.5, min_free_fraction=0.5) | band
    grid = m.project(**band)
    expected = project_csv(csv, m.resolution, **full)
    known = {k: v for k, v in expected.items() if v[1] != 0}
    assert sum(v[1] == 1 for v in known.values()) > 50 and sum(v[1] == -1 for v in known.values()) > 50

    # The rectangle spans exactly the known columns; row 0 is the south.
    xs = [k[0] for k in known]
    ys = [k[1] for k in known]
    assert grid.origin_key == (min(xs), min(ys))
    assert (grid.width, grid.height) == (max(xs) - min(xs) + 1, max(ys) - min(ys) + 1)
    assert grid.cost.shape == grid.column_class.shape == (grid.height, grid.width)
    assert grid.origin_x == pytest.approx(min(xs) * m.resolution)
    assert grid.origin_y == pytest.approx(min(ys) * m.resolution)
    assert grid.known_columns == len(known)

    # Every column, by its array index: the class exactly, the cost within 1 (the CSV rounds p and s).
    cost_diff = 0
    for row in range(grid.height):
        for col in range(grid.width):
            key = (grid.origin_key[0] + col, grid.origin_key[1] + row)
            want_cost, want_class = expected.get(key, (-1, 0))
            assert grid.column_class[row, col] == want_class, f"column {key}"
            if want_class == 0:
                assert grid.cost[row, col] == -1, f"column {key}"
            else:
                assert abs(int(grid.cost[row, col]) - want_cost) <= 1, f"column {key}"
                cost_diff += int(grid.cost[row, col]) != want_cost
    assert cost_diff <= len(known) // 100

    # column_at() reads the same grid by metres.
    for key, (cost, cls) in list(known.items())[:20]:
        x, y = (key[0] + 0.5) * m.resolution, (key[1] + 0.5) * m.resolution
        assert grid.column_at(x, y)[1] == cls


def test_projection_with_a_band_that_holds_no_layer_raises_value_error(lab):
    m, _ = lab
    with pytest.raises(ValueError, match="max_height"):
        m.project(min_height=1.0, max_height=0.5)
