"""Provenance of every output: file modes from the umask, units on every HDF5
dataset, format and library versions, JSON provenance entry, CSV sidecar; old files read."""

import json
import os

import h5py
import numpy as np
import pytest

from impactosc.dynamics.maps import MapResult, load_map, save_map
from impactosc.dynamics.sweep import (
    SweepResult,
    SweepSettings,
    load_sweep,
    save_sweep,
)
from impactosc.io.files import (
    DATASET_UNITS,
    FORMAT_VERSION,
    dataset_unit,
    provenance,
    provenance_path,
    read_csv,
    read_json,
    read_provenance,
    read_run,
    read_table,
    write_csv,
    write_json,
    write_run,
    write_table,
    write_text,
)
from impactosc.records.formats import read_record, read_record_set, write_record, write_record_set
from impactosc.records.record import Record

VERSION_KEYS = (
    "version",
    "git_commit",
    "python_version",
    "numpy_version",
    "scipy_version",
    "numba_version",
    "h5py_version",
)


def assert_stamped(path, sources=None, units=None):
    """Every dataset has a known unit; the root has the format version and the versions."""
    with h5py.File(path, "r") as f:
        names = []
        f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
        assert names
        for name in names:
            assert f[name].attrs["units"] == dataset_unit(name, units), name
        assert f.attrs["format_version"] == FORMAT_VERSION
        for key in VERSION_KEYS:
            assert f.attrs[key] and f.attrs[key] != "not installed", key
    if sources is not None:
        assert read_provenance(path)["sources"] == sources


def _run(path, **kw):
    events = {
        "impacts": {"t": [1.0, 2.0], "v": [0.1, 0.2], "sigma_t": [1e-4, 1e-4]},
        "penetrations": {"t": [1.1], "h": [1e-6]},
        "near_misses": {"t": [1.5], "gap": [1e-5]},
        "poincare": {"t": [0.0], "x": [-1e-3], "v": [0.0]},
    }
    traj = {"t": np.arange(3.0), "x": np.zeros(3), "v": np.zeros(3)}
    return write_run(path, events, {"omega": 40.86}, traj, **kw)


# ------------------------------------------------------------------------------ modes


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_written_files_respect_the_umask(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        paths = [
            write_text(tmp_path / "a.md", "x\n"),
            write_json(tmp_path / "a.json", {"a": 1}),
            write_csv(tmp_path / "a.csv", [{"a": 1}]),
            provenance_path(tmp_path / "a.csv"),
            _run(tmp_path / "a.h5"),
        ]
    finally:
        os.umask(old)
    for p in paths:
        assert os.stat(p).st_mode & 0o777 == mode, p


# ------------------------------------------------------------------------------ HDF5


def test_run_file_has_units_versions_and_sources(tmp_path):
    path = _run(tmp_path / "r.h5", sources=["in/record.csv"])
    assert_stamped(path, sources=["in/record.csv"])
    with h5py.File(path, "r") as f:
        assert f["impacts/v"].attrs["units"] == "m/s" and f["penetrations/h"].attrs["units"] == "m"
        assert f["trajectory/t"].attrs["units"] == "s" and f["impacts/sigma_t"].attrs["units"] == "s"
    _, attrs, traj = read_run(path)
    assert attrs["sources"] == ["in/record.csv"] and attrs["format_version"] == FORMAT_VERSION
    assert attrs["omega"] == 40.86 and traj["x"].shape == (3,)


def test_dataset_without_a_unit_is_refused(tmp_path):
    with pytest.raises(ValueError, match=r"no unit.*DATASET_UNITS"):
        write_run(tmp_path / "r.h5", {"impacts": {"t": [1.0], "mystery": [2.0]}}, {})
    assert list(tmp_path.iterdir()) == []


def test_read_run_reads_files_without_the_new_attributes(tmp_path):
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:  # the layout before format_version 1
        f.create_dataset("impacts/t", data=[1.0, 2.0])
        f.attrs["omega"] = 40.0
        f.attrs["version"] = "0.1.0"
        f.attrs["git_commit"] = "abc"
    events, attrs, traj = read_run(path)
    np.testing.assert_array_equal(events["impacts"]["t"], [1.0, 2.0])
    assert attrs == {"omega": 40.0, "version": "0.1.0", "git_commit": "abc"} and traj is None
    assert read_provenance(path) == {"version": "0.1.0", "git_commit": "abc"}


def test_sweep_map_and_record_files_are_stamped(tmp_path):
    n, k = 2, 3
    sweep = SweepResult(
        omega=np.array([40.0, 41.0]),
        poincare_x=np.zeros((n, k)),
        poincare_v=np.zeros((n, k)),
        impact_t=np.array([0.1, 0.2, 0.3]),
        impact_v=np.ones(3),
        impact_offsets=np.array([0, 1, 3]),
        min_gap=np.full(n, 1e-5),
        x_start=np.zeros(n),
        v_start=np.zeros(n),
        x_end=np.zeros(n),
        v_end=np.zeros(n),
        n_steps=np.array([10, 12]),
        wall_time=np.ones(n),
        cpu_time=np.ones(n),
        status=np.zeros(n, dtype=np.int64),
        settings=SweepSettings(n_transient=1, n_record=k, n_initial=0),
    )
    save_sweep(tmp_path / "s.h5", sweep, sources=[tmp_path / "seeds.h5"], name="t")
    assert_stamped(tmp_path / "s.h5", sources=[str(tmp_path / "seeds.h5")])
    back, attrs = load_sweep(tmp_path / "s.h5")
    assert attrs["name"] == "t" and back.settings == sweep.settings

    m = MapResult(
        "xI",
        np.array([-2e-3, -1e-3]),
        np.array([40.0, 41.0]),
        np.ones((2, 2)),
        np.ones((2, 2)),
        np.ones((2, 2)),
        np.ones((2, 2)),
    )
    save_map(tmp_path / "m.h5", m)
    assert_stamped(tmp_path / "m.h5", units={"values": "m"})
    with h5py.File(tmp_path / "m.h5", "r") as f:
        assert f["values"].attrs["units"] == "m" and f["omega"].attrs["units"] == "rad/s"
    assert load_map(tmp_path / "m.h5").parameter == "xI"
    with pytest.raises(ValueError, match="'values' has no unit"):
        save_map(tmp_path / "bad.h5", MapResult("c", m.values, m.omega, m.period, m.impacts, m.rate, m.n_isi_levels))

    t = np.arange(0.0, 1.0, 1e-3)
    x = -3e-3 + 1e-3 * np.sin(40.0 * t)
    write_record(tmp_path / "r.h5", t, x, omega=40.0, meta={"label": "rig"})
    assert_stamped(tmp_path / "r.h5")
    rec = read_record(tmp_path / "r.h5")
    assert rec.meta == {"label": "rig"}  # provenance is not record metadata
    write_record_set(tmp_path / "set.h5", [Record(t, x, 40.0), Record(t, x, 41.0)], sources="a.csv")
    assert_stamped(tmp_path / "set.h5", sources=["a.csv"])
    assert [r.omega for r in read_record_set(tmp_path / "set.h5")] == [40.0, 41.0]
    write_record(tmp_path / "r.csv", t, x, omega=40.0, units="mm")
    assert read_provenance(tmp_path / "r.csv")["file"] == "r.csv"
    assert read_record(tmp_path / "r.csv").omega == 40.0


def test_every_dataset_name_of_the_writers_has_a_unit():
    from impactosc.core.simulation import _COLUMNS
    from impactosc.dynamics.maps import _MAP_ARRAYS, VALUE_UNITS
    from impactosc.dynamics.sweep import _ARRAYS, MAP_PARAMETERS

    names = {c for cols in _COLUMNS.values() for c in cols} | set(_ARRAYS) | (set(_MAP_ARRAYS) - {"values"})
    names |= {"sigma_t", "record_omega", "n_points"}  # measured events, record-set Poincare points
    assert names <= set(DATASET_UNITS), names - set(DATASET_UNITS)
    assert set(MAP_PARAMETERS) <= set(VALUE_UNITS)


# ------------------------------------------------------------------------------ JSON, CSV


def test_json_has_a_provenance_entry_that_readers_skip(tmp_path):
    p = write_json(tmp_path / "s.json", {"a": np.float64(1.5)}, sources=[tmp_path / "run.h5", "b.h5"])
    raw = json.loads(p.read_text())
    assert list(raw) == ["a", "provenance"]
    prov = raw["provenance"]
    assert prov["sources"] == [str(tmp_path / "run.h5"), "b.h5"]
    assert {k: prov[k] for k in VERSION_KEYS} == provenance()
    assert read_json(p) == {"a": 1.5}
    assert read_json(p, keep_provenance=True)["provenance"] == prov == read_provenance(p)
    with pytest.raises(ValueError, match="provenance"):
        write_json(tmp_path / "x.json", {"provenance": 1})
    with pytest.raises(TypeError, match="dict"):
        write_json(tmp_path / "y.json", [1, 2])


def test_csv_provenance_sidecar_and_the_table_still_reads(tmp_path):
    rows = [{"a": 1.0 / 3, "ok": True, "w": [1.0, 2.0]}, {"a": 2.0, "ok": False, "w": [3.0]}]
    p = write_table(tmp_path / "t.csv", rows, sources=["x/part0.csv", "x/part1.csv"])
    assert p.read_text().splitlines()[0] == "a,ok,w"  # the table itself is plain CSV
    assert read_table(p)[0]["a"] == pytest.approx(1.0 / 3) and read_csv(p)[1]["ok"] == "no"
    side = provenance_path(p)
    assert side.name == "t.csv.provenance.json"
    prov = read_provenance(p)
    assert prov["file"] == "t.csv" and prov["sources"] == ["x/part0.csv", "x/part1.csv"]
    assert all(prov[k] for k in VERSION_KEYS)
    p.write_text(p.read_text() + "9,yes,1\n")  # changed behind the writer's back
    with pytest.raises(ValueError, match="sha256"):
        read_provenance(p)
