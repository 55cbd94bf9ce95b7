"""impactosc stats: the table, the JSON keys, --against, and errors that name the problem."""

import json

import h5py
import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.cli.stats import EXPLAINED
from impactosc.io.files import write_run


def _gamma_run(path, seed, span=120.0, t0=0.0, **extra):
    rng = np.random.default_rng(seed)
    t = t0 + np.cumsum(rng.gamma(4.0, 1 / 28, int(10 * span)))
    t = t[t < t0 + span]
    events = {"impacts": {"t": t}}
    if extra.get("penetrations"):
        events["penetrations"] = {"t": t, "h": rng.gamma(9.0, 1e-5, t.size)}
    write_run(path, events, {"t_start": t0, "t_stop": t0 + span})
    return t


def test_table_json_and_against(tmp_path, capsys):
    a = _gamma_run(tmp_path / "a.h5", 1, penetrations=True)
    _gamma_run(tmp_path / "b.h5", 2, t0=50.0, span=100.0)
    out = tmp_path / "ab.json"
    args = ["stats", str(tmp_path / "a.h5"), "--against", str(tmp_path / "b.h5"), "--surrogates", "19"]
    assert main([*args, "--json", str(out)]) == 0
    text = capsys.readouterr().out
    for label in ("CV2 (Holt)", "LvR", "C_V^2 as the paper (s)", "isi-distance", "spike-distance", "joint_isi p ="):
        assert label in text, label
    got = json.loads(out.read_text())
    for key in ("cv2", "lv", "lvr", "serial_correlation", "cv2_paper", "cv_squared", "fano", "window_counts"):
        assert key in got, key
    assert len(got["serial_correlation"]) == 10 and got["n_impacts"] == a.size
    assert got["penetration_modes"] and got["against"]["statistics"]["penetration_modes"] is None
    ag = got["against"]
    # --align start: each train from its own span's start, cut to the shorter span (100 s)
    assert ag["common_span"] == [0.0, 100.0] and ag["n_surrogates"] == 19
    for name in ("isi_distance", "spike_distance"):
        assert 0 < ag[name]["value"] < 1
        for kind in ("joint_isi", "shuffled"):
            p = ag[name]["tests"][kind]["pvalue"]
            assert 1 / 39 <= p <= 1 and (p * 39) == pytest.approx(round(p * 39))  # a multiple of 1/(2N+1)
    # the same call gives the same numbers (every surrogate from --seed)
    assert main([*args, "--json", str(tmp_path / "again.json")]) == 0
    assert json.loads((tmp_path / "again.json").read_text())["against"]["spike_distance"] == ag["spike_distance"]


def test_help_explains_every_statistic(capsys):
    with pytest.raises(SystemExit):
        main(["stats", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name, line in EXPLAINED:
        assert name in text and " ".join(line.split())[:40] in text, name


def _error(capsys, argv) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("impactosc stats: error:"), err
    return err


def test_errors_name_the_problem(tmp_path, capsys):
    assert "missing.h5 does not exist" in _error(capsys, ["stats", str(tmp_path / "missing.h5")])
    (tmp_path / "text.h5").write_text("not hdf5")
    assert "not an HDF5 file" in _error(capsys, ["stats", str(tmp_path / "text.h5")])
    with h5py.File(tmp_path / "empty.h5", "w") as f:
        f.create_group("poincare").create_dataset("t", data=np.arange(5.0))
    assert "no impacts/t dataset" in _error(capsys, ["stats", str(tmp_path / "empty.h5")])
    write_run(tmp_path / "few.h5", {"impacts": {"t": np.arange(1.0, 6.0)}}, {"t_start": 0.0, "t_stop": 10.0})
    err = _error(capsys, ["stats", str(tmp_path / "few.h5")])
    assert "5 impacts" in err and "at least 10" in err
    _gamma_run(tmp_path / "ok.h5", 3)
    err = _error(capsys, ["stats", str(tmp_path / "ok.h5"), "--against", str(tmp_path / "missing.h5")])
    assert "--against" in err and "does not exist" in err
    _gamma_run(tmp_path / "late.h5", 4, t0=500.0)
    err = _error(
        capsys, ["stats", str(tmp_path / "ok.h5"), "--against", str(tmp_path / "late.h5"), "--align", "absolute"]
    )
    assert "do not overlap" in err
    assert "--refractoriness" in _error(capsys, ["stats", str(tmp_path / "ok.h5"), "--refractoriness", "-1"])
    assert "--surrogates" in _error(capsys, ["stats", str(tmp_path / "ok.h5"), "--surrogates", "0"])
    assert "does not exist" in _error(
        capsys, ["stats", str(tmp_path / "ok.h5"), "--json", str(tmp_path / "no" / "x.json")]
    )


def test_too_few_events_for_a_statistic(tmp_path, capsys):
    # 12 impacts in a 2 s span: the Fano curve's windows (0.25 s .. ) fit, the stationarity test
    # runs; a part that cannot be computed is named with the count
    write_run(tmp_path / "short.h5", {"impacts": {"t": np.linspace(0.1, 0.3, 12)}}, {"t_start": 0.0, "t_stop": 0.35})
    err = _error(capsys, ["stats", str(tmp_path / "short.h5")])
    assert "12 impacts, too few for the" in err
