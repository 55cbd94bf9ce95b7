"""Command line and HDF5 contract: datasets, attributes, clear errors, atomic writes."""

import os
import subprocess
import sys

import h5py
import numpy as np
import pytest
from test_provenance import assert_stamped  # tests/ is on sys.path (pytest's prepend import mode)

from impactosc.cli import main as cli
from impactosc.io.files import read_run, write_run

EXE = [sys.executable, "-m", "impactosc.cli.main"]


def run_cli(*args):
    return subprocess.run(EXE + list(args), capture_output=True, text=True, timeout=300)


def test_simulate_writes_the_contract(tmp_path):
    out = tmp_path / "run.h5"
    r = run_cli(
        "simulate",
        "--omega",
        "40.86",
        "--transient",
        "1",
        "--duration",
        "2",
        "--window",
        "2",
        "2.5",
        "0.001",
        "--output",
        str(out),
    )
    assert r.returncode == 0, r.stderr
    assert "impacts" in r.stdout and "wall time" in r.stdout
    with h5py.File(out) as f:
        for name in (
            "impacts/t",
            "impacts/v",
            "penetrations/t",
            "penetrations/h",
            "near_misses/t",
            "near_misses/gap",
            "poincare/t",
            "poincare/x",
            "poincare/v",
            "trajectory/t",
            "trajectory/x",
            "trajectory/v",
        ):
            assert name in f, name
        for key in (
            "param_m",
            "param_kI",
            "param_xI",
            "omega",
            "transient",
            "duration",
            "x0",
            "v0",
            "solver",
            "rtol",
            "atol",
            "n_steps",
            "n_rejected",
            "n_rhs",
            "wall_time",
        ):
            assert key in f.attrs, key
        datasets = []
        f.visititems(lambda name, obj: datasets.append(name) if isinstance(obj, h5py.Dataset) else None)
        assert len(datasets) == 12
        assert f["impacts/v"].attrs["units"] == "m/s" and f["trajectory/t"].attrs["units"] == "s"
        assert f.attrs["omega"] == 40.86
        assert np.all(f["impacts/t"][()] >= 1.0)
        assert np.all(f["penetrations/h"][()] > 0)
        assert len(f["trajectory/t"]) == 501
    assert_stamped(out)  # every dataset's unit, the format version, package and library versions
    assert [p.name for p in tmp_path.iterdir()] == ["run.h5"]  # no temporary left behind


@pytest.mark.parametrize(
    "args, message",
    [
        (["--omega", "40", "--transient", "1", "--duration", "-1"], "duration must be > 0"),
        (["--omega", "nan", "--transient", "1", "--duration", "1"], "not finite"),
        (["--omega", "-3", "--transient", "1", "--duration", "1"], "omega must be > 0"),
        (["--omega", "40", "--transient", "-1", "--duration", "1"], "transient must be >= 0"),
        (["--omega", "40", "--transient", "1", "--duration", "1", "--rtol", "0"], "rtol must be in (0, 1)"),
        (["--omega", "40", "--transient", "1", "--duration", "1", "--window", "0", "9", "0.1"], "window"),
        (["--omega", "40", "--transient", "1", "--duration", "1", "--events", "impacts,foo"], "unknown event"),
    ],
)
def test_bad_input_is_one_clear_line_and_writes_nothing(tmp_path, args, message):
    out = tmp_path / "x.h5"
    r = run_cli("simulate", *args, "--output", str(out))
    assert r.returncode == 2
    assert message in r.stderr
    *usage, last = r.stderr.strip().splitlines()
    assert last.startswith("impactosc simulate: error:")  # one line; argparse puts its usage before it
    assert all(line.startswith(("usage:", " ")) for line in usage), usage
    assert not out.exists()


def test_unwritable_output_fails_before_computing(tmp_path):
    r = run_cli(
        "simulate",
        "--omega",
        "40",
        "--transient",
        "1",
        "--duration",
        "1",
        "--output",
        str(tmp_path / "missing" / "x.h5"),
    )
    assert r.returncode == 2 and "does not exist" in r.stderr


def test_help_explains_units():
    text = cli.build_parser()._subparsers._group_actions[0].choices["simulate"].format_help()
    for needle in ("rad/s", "--transient", "--window", "absolute times", "m/s", "atomically"):
        assert needle in text


def test_interrupted_write_leaves_no_file(tmp_path, monkeypatch):
    out = tmp_path / "run.h5"

    def boom(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(h5py.Group, "create_dataset", boom)
    with pytest.raises(KeyboardInterrupt):
        write_run(out, {"impacts": {"t": [1.0]}}, {"omega": 1.0})
    assert list(tmp_path.iterdir()) == []


def test_read_run_roundtrip_and_missing_file(tmp_path):
    out = write_run(
        tmp_path / "r.h5",
        {"impacts": {"t": np.arange(3.0), "v": np.ones(3)}},
        {"omega": 2.0},
        {"t": np.arange(2.0), "x": np.zeros(2), "v": np.zeros(2)},
    )
    events, attrs, traj = read_run(out)
    np.testing.assert_array_equal(events["impacts"]["t"], np.arange(3.0))
    assert attrs["omega"] == 2.0 and "git_commit" in attrs
    assert traj["x"].shape == (2,)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        read_run(tmp_path / "nope.h5")
    assert os.listdir(tmp_path) == ["r.h5"]


def test_uncompressed_run_reads_back_the_same(tmp_path):
    events = {"impacts": {"t": np.arange(3.0), "v": np.ones(3)}}
    traj = {"t": np.linspace(0.0, 1.0, 1000), "x": np.sin(np.arange(1000.0)), "v": np.cos(np.arange(1000.0))}
    packed, plain = (
        write_run(tmp_path / f"{name}.h5", events, {}, traj, compress=name == "packed") for name in ("packed", "plain")
    )
    with h5py.File(packed) as f, h5py.File(plain) as g:
        assert f["trajectory/x"].compression == "gzip" and g["trajectory/x"].compression is None
    for name in ("t", "x", "v"):
        np.testing.assert_array_equal(read_run(plain)[2][name], read_run(packed)[2][name])


def test_predict_refuses_an_unknown_table_suffix_before_computing(tmp_path, capsys):
    from impactosc.model.model_file import write_model_file
    from impactosc.model.parameters import ModelParams

    model = write_model_file(tmp_path / "bc.yaml", ModelParams())
    assert cli.main(["predict", str(model), "--output", str(tmp_path / "points.txt")]) == 2
    err = capsys.readouterr().err
    assert (
        err
        == f"impactosc predict: error: --output: {tmp_path / 'points.txt'}: the table is written as .csv or .md (by its suffix)\n"
    )


def test_predict_without_located_points_writes_an_empty_table(tmp_path, capsys):
    from impactosc.io.files import read_csv
    from impactosc.model.model_file import write_model_file
    from impactosc.model.parameters import ModelParams

    model = write_model_file(tmp_path / "bc.yaml", ModelParams())
    out = tmp_path / "points.csv"
    assert cli.main(["predict", str(model), "--w-range", "20", "20.01", "--quiet", "--output", str(out)]) == 0
    assert "no grazing, period doubling or fold" in capsys.readouterr().out
    assert out.read_text().splitlines() == ["segment,kind,omega,n_periods,se,note"] and read_csv(out) == []
