"""ogf.load_map: a map made by ogf-map from the simulated lab, read as numpy arrays, equals the map's
`ogf-map --export-csv` cell for cell; its point and box queries agree with the CSV; its errors name the file."""

import errno

import numpy as np
import pytest

import ogf
from conftest import read_cell_csv


@pytest.fixture(scope="module")
def lab(lab_map):
    return ogf.load_map(lab_map["map"]), read_cell_csv(lab_map["csv"])


def test_arrays_equal_the_csv_export_cell_for_cell(lab):
    m, csv = lab
    n = len(csv["p"])
    assert n > 1000 and len(m) == n
    assert m.keys.shape == (n, 3) and m.keys.dtype == np.int32
    assert m.centres.shape == (n, 3) and m.centres.dtype == np.float64
    assert m.probability.shape == (n,) and m.probability.dtype == np.float64
    assert m.variance.shape == (n,) and m.variance.dtype == np.float32
    assert m.cell_class.shape == (n,) and m.cell_class.dtype == np.int8
    # The CSV prints centres with 4 decimals, p with 6 and the variance with 6 significant digits.
    np.testing.assert_allclose(m.centres, csv["centres"], rtol=0, atol=5.1e-5)
    np.testing.assert_allclose(m.probability, csv["p"], rtol=0, atol=5.1e-7)
    np.testing.assert_allclose(m.variance, csv["variance"], rtol=5.1e-6, atol=1e-30)
    np.testing.assert_array_equal(m.cell_class, csv["cls"])
    # The keys are the cells the centres lie in.
    np.testing.assert_array_equal(m.keys, np.floor(m.centres / m.resolution).astype(np.int32))
    assert {-1, 1} <= set(np.unique(m.cell_class).tolist())


def test_map_file_attributes_say_what_was_read(lab, lab_map):
    m, _ = lab
    assert m.kind == "map file" and m.seq == -1
    assert m.resolution == pytest.approx(0.2)
    assert m.path == str(lab_map["map"])
    assert not m.probability.flags.writeable


def test_point_query_agrees_with_the_csv_rows(lab):
    m, csv = lab
    rows = np.concatenate([np.flatnonzero(csv["cls"] == c)[:20] for c in (-1, 0, 1)])
    assert len(rows) >= 40
    for i in rows:
        x, y, z = csv["centres"][i]
        q = m.query(x, y, z)
        assert q["allocated"]
        assert q["key"] == tuple(m.keys[i])
        assert q["probability"] == pytest.approx(csv["p"][i], abs=5.1e-7)
        assert q["cell_class"] == csv["cls"][i]
        assert q["variance"] == pytest.approx(csv["variance"][i], rel=5.1e-6)
        # Eq. (3) thresholds Phi(m): the class follows from the occupancy probability and the mean's sign.
        assert (q["occupancy_probability"] > 0.5) == (q["mean"] > 0)
        assert 0.0 <= q["entropy_bits"] <= 1.0


def test_point_query_of_a_cell_never_allocated_answers_the_prior(lab):
    m, _ = lab
    q = m.query(1000.0, 1000.0, 1000.0)
    assert not q["allocated"]
    assert q["probability"] == 0.5 and q["cell_class"] == 0 and q["mean"] == 0.0
    assert q["entropy_bits"] == pytest.approx(1.0)


def test_box_query_counts_the_classes_of_the_csv_cells_inside(lab):
    m, csv = lab
    lo = np.array([-2.0, -2.0, 0.1])
    hi = np.array([2.0, 2.0, 1.1])
    s = m.query_box(lo, hi)
    klo = np.floor(lo / m.resolution).astype(int)
    khi = np.floor(hi / m.resolution).astype(int)
    assert s["cells"] == int(np.prod(khi - klo + 1))
    inside = np.all((m.keys >= klo) & (m.keys <= khi), axis=1)
    assert s["allocated"] == int(inside.sum()) > 0
    assert s["occupied"] == int((csv["cls"][inside] == 1).sum())
    assert s["free"] == int((csv["cls"][inside] == -1).sum())
    # Unallocated cells are unknown, as are allocated cells of class 0.
    assert s["unknown"] == s["cells"] - s["occupied"] - s["free"]


def test_box_query_with_lo_above_hi_raises_value_error(lab):
    m, _ = lab
    with pytest.raises(ValueError, match="box"):
        m.query_box((1.0, 0.0, 0.0), (0.0, 1.0, 1.0))


def test_missing_file_raises_file_not_found_naming_it(tmp_path):
    missing = tmp_path / "no-such-map.ogfs"
    with pytest.raises(FileNotFoundError) as e:
        ogf.load_map(missing)
    assert e.value.errno == errno.ENOENT
    assert e.value.filename == str(missing)
    assert str(missing) in str(e.value)


def test_damaged_file_raises_map_file_error_with_the_loaders_reason(tmp_path, lab_map):
    damaged = tmp_path / "damaged.ogfm"
    data = bytearray(lab_map["map"].read_bytes())
    damaged.write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(ogf.MapFileError) as e:
        ogf.load_map(str(damaged))
    assert isinstance(e.value, ValueError)
    assert str(damaged) in str(e.value)
    assert "neither a map file" in str(e.value)


def test_file_that_is_not_a_map_raises_map_file_error(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("not a map\n")
    with pytest.raises(ogf.MapFileError, match="notes.txt"):
        ogf.load_map(text)
