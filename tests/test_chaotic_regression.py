"""Regression of the chaotic-train statistics on a shortened chaos scene, and Figs 6-11.

The short scene is the paper's (w = 40.86, from rest, 100 s transient, rtol 1e-10) with 100 s
of record instead of 400 s.  Reference values and their spread over 8 independent 100 s
realisations (other initial states) are stored in tests/data/chaotic_short_reference.json,
written by tests/data/make_chaotic_short_reference.py.

Tolerance: a chaotic trajectory is bit-reproducible only with the same compiler and CPU;
elsewhere the run here and the stored one are two independent realisations of the same
attractor, whose difference has standard deviation sqrt(2) * sd (sd = spread of the
realisations).  Allowing 4 * sqrt(2) * sd keeps a false alarm below 1e-4 per statistic
while a broken event detector or statistic (e.g. impacts lost, a wrong variance) moves the
numbers by many sd.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate
from impactosc.io.files import read_json, write_json, write_run
from impactosc.statistics import train_analysis as ch
from impactosc.statistics.ensemble import ensemble_summary
from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain, load_train
from impactosc.statistics.spectral_lines import trajectory_spectrum
from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure
from impactosc_study.paper.rows.chaotic import chaotic_rows
from impactosc_study.paper.table import write_rows

REF = json.loads((Path(__file__).parent / "data" / "chaotic_short_reference.json").read_text())
SCENE = REF["scene"]
OPTIONS = AnalysisOptions.from_config(REF["options"])
CONTINUOUS = ("n_impacts", "cv2_paper", "cv2", "isi_first_maximum", "isi_last_maximum", "acf_peak_frequency")


def _short_run(x0=0.0, window=None):
    res = simulate(
        SCENE["omega"],
        SCENE["transient"],
        SCENE["duration"],
        x0=x0,
        rtol=SCENE["rtol"],
        window=window,
        record=("impacts", "penetrations", "poincare"),
    )
    return res


def _stats(res, label):
    train = ImpactTrain(
        res.events["impacts"]["t"],
        SCENE["transient"],
        SCENE["transient"] + SCENE["duration"],
        penetrations=res.events["penetrations"]["h"],
        omega=SCENE["omega"],
        label=label,
    )
    return ch.analyse_train(train, OPTIONS)


@pytest.fixture(scope="module")
def short_run():
    return _short_run(window=Window(SCENE["transient"], SCENE["transient"] + 10.0, 2e-3))


@pytest.fixture(scope="module")
def short_stats(short_run):
    return _stats(short_run, "model")


@pytest.mark.parametrize("key", CONTINUOUS)
def test_short_scene_statistic(short_stats, key):
    value = ch.key_numbers(short_stats)[key]
    ref = REF["reference"][key]
    tol = 4 * math.sqrt(2) * REF["realisations"]["sd"][key]
    assert abs(value - ref) <= tol, f"{key}: {value} vs reference {ref} +/- {tol}"


def test_short_scene_conclusions(short_stats):
    """Verdicts that hold in every realisation: stationary, non-Poisson, bimodal, f = 1/3."""
    ref = REF["reference"]
    assert short_stats["stationarity"]["rejected"] == ref["equal_rate_rejected"] is False
    assert short_stats["poisson"]["rejected"] == ref["ks_rejected"] is True
    assert short_stats["mixture"]["best_by_k"]["2"] == ref["mixture_best_2"]
    assert short_stats["isi_density"]["n_modes"] >= 2
    # the paper's C_V^2 (var/mean, s) is the dimensionless CV^2 times the mean interval
    v = short_stats["variability"]
    assert v["cv2_paper"] == pytest.approx(v["cv2"] * short_stats["train"]["mean_isi"], rel=1e-3)
    # 100 s is short for the penetration modes: 2 or 3 are found (realisations: 2-3)
    assert short_stats["penetrations"]["n_modes"] >= 2


def test_paper_rows_are_well_formed(short_stats, short_run, tmp_path):
    other = _stats(_short_run(x0=1e-3), "other")
    ens = ensemble_summary({"a": ch.key_numbers(short_stats), "b": ch.key_numbers(other)})
    traj = short_run.trajectory
    spectrum = trajectory_spectrum(traj["t"], traj["x"], SCENE["omega"])
    rows = chaotic_rows(read_json(write_json(tmp_path / "m.json", short_stats)), ens, spectrum, "cmd")
    write_rows(tmp_path / "rows.csv", rows)  # checks the columns
    assert all(r["section"].startswith("2.2") and r["agrees"] in ("yes", "no", "n.a.") for r in rows)
    by = {r["quantity"]: r for r in rows}
    # scale-free rows agree already on 100 s; the 400 s counts obviously do not
    assert by["Fig 8a: C_V^2 as computed (var/mean of the ISIs, s), large i"]["agrees"] == "yes"
    assert by["Fig 6b: dominant spectral peak of x (rad/s)"]["agrees"] == "yes"
    assert by["impacts in the 400 s record"]["agrees"] == "no"
    assert ch.mixture_table(short_stats)[0]["delta_bic"] == "0.00"


def test_figures_build(short_stats, short_run, tmp_path):
    """Figs 6-11 render from a run file / statistics JSONs, with and without a second train."""
    run = write_run(tmp_path / "run.h5", short_run.events, short_run.attrs, short_run.trajectory)
    model = write_json(tmp_path / "model.json", short_stats)
    # a second train as a measured record may come: no penetrations, no forcing frequency,
    # span from its first and last impact
    bare = write_run(tmp_path / "bare.h5", {"impacts": short_run.events["impacts"]}, {})
    second_stats = ch.analyse_train(load_train(bare, label="surrogate"), OPTIONS)
    assert second_stats["penetrations"] is None and "forcing_period" not in second_stats["isi_density"]
    second = write_json(tmp_path / "second.json", second_stats)
    for nn, kw in (
        (6, {"run": run, "portrait_span": 5.0}),
        (7, {"run": run}),
        (8, {"stats": [model, second]}),
        (9, {"stats": [model]}),
        (10, {"stats": [model, second]}),
        (11, {"stats": [model]}),
    ):
        fig = make_figure(nn, **kw)
        labels = [ax.get_title(loc="left") for ax in fig.axes]
        if nn in (8, 10):
            assert any("surrogate" in s for s in labels)  # the second train keeps its label
        png = tmp_path / f"fig{nn:02d}.png"
        save_figure(fig, png)
        assert png.stat().st_size > 10_000


def test_figure_input_errors(short_stats, short_run, tmp_path):
    with pytest.raises(ValueError, match="not in the chaotic group"):
        make_figure(5, stats=["x.json"])
    with pytest.raises(ValueError, match="needs the scene's run file"):
        make_figure(6)
    bare = write_run(tmp_path / "bare.h5", short_run.events, short_run.attrs)
    with pytest.raises(ValueError, match="no trajectory window"):
        make_figure(6, run=bare)
    no_pen = write_json(tmp_path / "np.json", dict(short_stats, penetrations=None))
    with pytest.raises(ValueError, match="no penetrations"):
        make_figure(11, stats=[no_pen])


@pytest.mark.slow
def test_full_scene_against_paper(tmp_path):
    """The 400 s scene and three more realisations reproduce the paper's section 2.2."""
    runs = [
        simulate(
            40.86,
            100.0,
            400.0,
            x0=x0,
            record=("impacts", "penetrations"),
            window=Window(100.0, 500.0, 2e-3) if x0 == 0 else None,
        )
        for x0 in (0.0, 5e-4, -5e-4, 1e-3)
    ]
    opts = AnalysisOptions()
    stats = []
    for i, r in enumerate(runs):
        tr = ImpactTrain(
            r.events["impacts"]["t"],
            100.0,
            500.0,
            penetrations=r.events["penetrations"]["h"],
            omega=40.86,
            label=f"r{i}",
        )
        stats.append(ch.analyse_train(tr, opts))
    ens = ensemble_summary({s["train"]["label"]: ch.key_numbers(s) for s in stats})
    spectrum = trajectory_spectrum(runs[0].trajectory["t"], runs[0].trajectory["x"], 40.86)
    model = read_json(write_json(tmp_path / "full.json", stats[0]))
    rows = {r["quantity"]: r for r in chaotic_rows(model, ens, spectrum, "slow test")}
    for q, r in rows.items():
        if q.startswith(("impacts in", "Fig 10")):
            continue  # judged against a 12-run ensemble in the workflow; 4 runs are too few
        assert r["agrees"] in ("yes", "n.a."), r
    counts = [s["train"]["n_impacts"] for s in stats]
    assert all(abs(n - 2875) <= 45 for n in counts), counts  # 1.5 %: see test_core_scenes
    assert all(abs(s["acf"]["peak_frequency"][0] - 1 / 3) < 0.02 for s in stats)
    assert np.all([s["mixture"]["best"] == "gamma x3" for s in stats])
