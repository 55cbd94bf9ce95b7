"""Measured-record reading: the format round-trips and bad records are refused by line."""

import numpy as np
import pytest

from impactosc.records import _csv as record_csv
from impactosc.records.formats import read_record, read_record_set, write_record, write_record_set

HEADER = "# units: mm\n# omega: 40.86\nt,x\n"


def _csv(tmp_path, body, header=HEADER, name="r.csv"):
    p = tmp_path / name
    p.write_text(header + body)
    return p


def _rows(n=200, dt=1e-3, t0=0.0):
    t = t0 + dt * np.arange(n)
    return "".join(f"{a:.6f},{-3 + np.sin(40.86 * a):.6f}\n" for a in t)


def test_example_record_reads_in_metres():
    rec = read_record("examples/record_example.csv")
    assert rec.omega == pytest.approx(40.86)
    assert rec.meta["x_impact"] == pytest.approx(-2.086e-3)  # declared in mm, returned in m
    assert np.ptp(rec.x) < 0.05 and rec.dt == pytest.approx(1e-3)
    assert "surrogate" in rec.label


@pytest.mark.parametrize("suffix", [".csv", ".h5"])
def test_roundtrip(tmp_path, suffix):
    t = np.arange(600) * 5e-4
    x = -2e-3 + 1e-3 * np.sin(30 * t)
    p = write_record(tmp_path / f"r{suffix}", t, x, omega=30.0, meta={"label": "rig"}, units="mm")
    rec = read_record(p)
    np.testing.assert_allclose(rec.x, x, rtol=0, atol=1e-10)  # CSV keeps 9 significant digits of ~3 mm: 1e-11 m
    assert rec.omega == 30.0 and rec.label == "rig"


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda L: L.__setitem__(10, "0.010000,nan"), "line 14: displacement is nan"),
        (lambda L: L.__setitem__(10, L[9]), "line 14: time stamp .* is repeated"),
        (lambda L: L.__setitem__(10, "0.001000,-3.0"), "line 14: time stamp .* is unsorted"),
        (lambda L: L.__setitem__(10, "0.010000,abc"), "line 14: non-numeric"),
        (lambda L: L.__delitem__(slice(10, 15)), "line 14: gap of 0.006 s"),
    ],
)
def test_malformed_lines_are_named(tmp_path, mutate, message):
    lines = _rows().splitlines()
    mutate(lines)
    p = _csv(tmp_path, "\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=message):
        read_record(p)


def test_wrong_or_missing_units(tmp_path):
    rows = _rows()
    with pytest.raises(ValueError, match="units not declared"):
        read_record(_csv(tmp_path, rows, header="t,x\n"))
    with pytest.raises(ValueError, match="declared as m"):  # mm values declared as metres
        read_record(_csv(tmp_path, rows, header="# units: m\nt,x\n"))
    with pytest.raises(ValueError, match="unknown units"):
        read_record(_csv(tmp_path, rows, header="# units: inch\nt,x\n"))


def test_shorter_than_one_period(tmp_path):
    with pytest.raises(ValueError, match="shorter than one forcing period"):
        read_record(_csv(tmp_path, _rows(n=100)))  # 0.1 s < 2 pi / 40.86 = 0.154 s


def test_missing_column_and_file(tmp_path):
    with pytest.raises(ValueError, match="no column 'y'"):
        read_record(_csv(tmp_path, _rows()), x_column="y")
    with pytest.raises(FileNotFoundError):
        read_record(tmp_path / "absent.csv")


def test_record_set_manifest_and_h5(tmp_path):
    recs = []
    for w in (30.0, 31.0):
        t = np.arange(400) * 1e-3
        write_record(tmp_path / f"w{w:g}.csv", t, -3e-3 + 1e-3 * np.sin(w * t), units="mm")
        recs.append(read_record(tmp_path / f"w{w:g}.csv", omega=w))
    (tmp_path / "set.csv").write_text("omega,file\n30,w30.csv\n31,w31.csv\n")
    a = read_record_set(tmp_path / "set.csv")
    write_record_set(tmp_path / "set.h5", recs)
    b = read_record_set(tmp_path / "set.h5")
    assert [r.omega for r in a] == [r.omega for r in b] == [30.0, 31.0]
    np.testing.assert_array_equal(a[1].x, b[1].x)


def _read_both(path, monkeypatch):
    """read_record through the loadtxt fast path (asserting numpy took it), then line by line."""
    real, taken = record_csv._loadtxt_columns, []
    monkeypatch.setattr(record_csv, "_loadtxt_columns", lambda *a: taken.append(real(*a)) or taken[-1])
    fast = read_record(path)
    assert taken and taken[-1] is not None  # numpy parsed the whole block
    monkeypatch.setattr(record_csv, "_loadtxt_columns", lambda *a: None)  # force the fallback
    return fast, read_record(path)


def test_loadtxt_fast_path_equals_line_parser(tmp_path, monkeypatch):
    # 17 significant digits, an extra column and an empty line: both parsers round each
    # field correctly, so the arrays must be bit-identical
    rng = np.random.default_rng(4)
    t = 100.0 + 1e-3 * np.arange(5000) + rng.uniform(-1e-5, 1e-5, 5000)
    x = -2.0 + np.sin(40.86 * t) + rng.normal(0, 1e-3, 5000)
    rows = [f"{float(a)!r},{float(b)!r},{i}" for i, (a, b) in enumerate(zip(t, x))]
    rows.insert(100, "")
    p = _csv(tmp_path, "\n".join(rows) + "\n", header="# units: mm\nt,x,i\n")
    fast, slow = _read_both(p, monkeypatch)
    np.testing.assert_array_equal(fast.t, slow.t)
    np.testing.assert_array_equal(fast.x, slow.x)
    np.testing.assert_array_equal(fast.t, t)
    np.testing.assert_array_equal(fast.x, x * 1e-3)


def test_example_record_same_through_both_parsers(monkeypatch):
    a, b = _read_both("examples/record_example.csv", monkeypatch)
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.x, b.x)
    assert (a.omega, a.meta) == (b.omega, b.meta)
    # and the values read before the fast path existed (commit 29f74da)
    assert a.t.size == 401 and a.t[0] == 100.0 and a.x[0] == -0.0138029978


@pytest.mark.parametrize(
    "mutate, message",
    [
        # an empty line (skipped by both parsers) before a bad sample: the line number counts it
        (lambda L: (L.__setitem__(10, "0.010000,nan"), L.insert(5, "")), "line 15: displacement is nan"),
        (lambda L: (L.__setitem__(10, "0.001000,-3.0"), L.insert(5, "")), "line 15: time stamp .* is unsorted"),
        # whitespace-only line, ragged row, quoted field: loadtxt declines, the line parser decides
        (lambda L: (L.__setitem__(10, "0.010000,nan"), L.insert(5, "   ")), "line 15: displacement is nan"),
        (lambda L: L.__setitem__(10, "0.010000,-3.0,7"), "line 14: 3 fields, the header has 2"),
        (lambda L: L.__setitem__(10, "0.010000"), "line 14: 1 fields, the header has 2"),
        (lambda L: L.__setitem__(10, '"0.010000",abc'), "line 14: non-numeric"),
    ],
)
def test_fast_path_errors_name_the_line(tmp_path, mutate, message):
    lines = _rows().splitlines()
    mutate(lines)
    with pytest.raises(ValueError, match=message):
        read_record(_csv(tmp_path, "\n".join(lines) + "\n"))


def test_quoted_fields_fall_back_to_line_parser(tmp_path):
    lines = _rows().splitlines()
    a = read_record(_csv(tmp_path, "\n".join(lines) + "\n", name="a.csv"))
    lines[3] = '"{}","{}"'.format(*lines[3].split(","))
    b = read_record(_csv(tmp_path, "\n".join(lines) + "\n", name="b.csv"))
    np.testing.assert_array_equal(a.x, b.x)


@pytest.mark.parametrize(("body", "n"), [("", 0), ("0.0,-3.0\n", 1)])
def test_a_record_without_samples_or_with_one_is_refused_by_name(tmp_path, body, n):
    from impactosc.records.streams import open_record_stream

    path = _csv(tmp_path, body)
    message = f"{path}: only {n} samples; a record needs at least 20"
    for read in (read_record, open_record_stream):
        with pytest.raises(ValueError) as refused:
            read(path)
        assert str(refused.value) == message


def test_a_line_longer_than_the_limit_is_refused_without_its_text(tmp_path):
    """Also a file without any line break: refused after one block, not scanned block by block."""
    long = "x" * (record_csv.MAX_LINE_CHARS + 1)
    for name, text in (("header.csv", f"t,{long}\n0,1\n"), ("no_breaks.csv", "1" * (4 * record_csv.BLOCK_CHARS))):
        p = tmp_path / name
        p.write_text(text)
        with pytest.raises(ValueError) as refused:
            read_record(p)
        assert str(refused.value).startswith(f"{p}: line 1 is longer than {record_csv.MAX_LINE_CHARS} characters")
        assert len(str(refused.value)) < 300
    rows = _rows(50)
    p = _csv(tmp_path, rows + "1" * (record_csv.MAX_LINE_CHARS + 1) + "\n" + rows, name="middle.csv")
    with pytest.raises(ValueError, match=f"line {3 + 50 + 1} is longer than"):
        read_record(p)
