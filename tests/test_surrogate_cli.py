"""Surrogate records, the extract/surrogate CLI, and the panel-label guard."""

import h5py
import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.io.files import read_run
from impactosc.records.formats import read_record, read_record_set, write_record_set
from impactosc.records.poincare import record_set_poincare
from impactosc.records.surrogate import (
    LABEL,
    SurrogateOptions,
    butterworth_delay,
    mismatched_params,
    surrogate_record,
    surrogate_sweep,
)


def test_surrogate_is_labelled_and_noisy():
    rec, _truth = surrogate_record(40.86, 10.0, 2.0, SurrogateOptions(rate=1000, noise=1e-5, seed=3))
    assert rec.label == LABEL and rec.meta["source"] == "surrogate"
    assert rec.dt == pytest.approx(1e-3) and rec.t[0] == 10.0
    clean, _ = surrogate_record(40.86, 10.0, 2.0, SurrogateOptions(rate=1000, noise=0.0))
    resid = rec.x - clean.x
    assert np.std(resid) == pytest.approx(1e-5, rel=0.1)  # 2001 samples: std known to ~3 %


def test_mismatch_validation():
    p = mismatched_params(None, {"c": 0.02})
    assert p.c == pytest.approx(6.6511 * 1.02)
    with pytest.raises(ValueError, match="unknown model parameter"):
        mismatched_params(None, {"zeta": 0.1})
    with pytest.raises(ValueError, match="small relative change"):
        mismatched_params(None, {"c": 0.9})


def test_sweep_record_set_roundtrip(tmp_path):
    recs = surrogate_sweep([30.0, 30.5], 20, 5, SurrogateOptions(rate=1000, noise=0.0), n_initial=200)
    write_record_set(tmp_path / "s.h5", recs)
    back = read_record_set(tmp_path / "s.h5")
    pts = record_set_poincare(back)
    assert list(pts["record_omega"]) == [30.0, 30.5]
    assert pts["x"].size == pts["n_points"].sum() >= 8
    # each record spans 5 periods exactly: 5 or 6 section points inside it
    assert set(pts["n_points"]) <= {5, 6}


def test_cli_surrogate_then_extract(tmp_path, capsys):
    rec = tmp_path / "r.csv"
    assert (
        main(
            [
                "surrogate",
                "--omega",
                "40.86",
                "--transient",
                "50",
                "--duration",
                "5",
                "--rate",
                "2000",
                "--noise",
                "2e-6",
                "--units",
                "mm",
                "--output",
                str(rec),
            ]
        )
        == 0
    )
    out = tmp_path / "ev.h5"
    assert main(["extract", str(rec), "--x-impact=-2.086e-3", "--output", str(out)]) == 0
    events, attrs, _ = read_run(out)
    assert {"impacts", "penetrations", "poincare"} <= set(events)
    assert attrs["x_impact"] == pytest.approx(-2.086e-3) and attrs["x_impact_source"] == "given"
    assert events["impacts"]["t"].size > 10 and attrs["omega"] == pytest.approx(40.86)
    # without --x-impact the record's metadata is used (the surrogate knows its obstacle)
    assert main(["extract", str(rec), "--output", str(out)]) == 0
    assert "record metadata" in capsys.readouterr().out


def test_cli_extract_rejects_bad_record(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text(
        "# units: mm\nt,x\n" + "".join(f"{0.001 * k},{-3.0}\n" for k in range(50)).replace("0.01,", "0.009,", 1)
    )
    assert main(["extract", str(bad), "--output", str(tmp_path / "e.h5")]) == 2
    assert "line 13: time stamp" in capsys.readouterr().err


def test_example_extracts():
    rec = read_record("examples/record_example.csv")
    from impactosc.records.extract import extract_events

    ev, at = extract_events(rec)
    assert ev["impacts"]["t"].size >= 2 and at["x_impact_source"] == "record metadata"


def test_noise_study_and_rows():
    from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain
    from impactosc.statistics.train_analysis import analyse_train
    from impactosc_study.noise_study import noise_study
    from impactosc_study.paper.rows.measured import measured_rows

    o = AnalysisOptions(acf_surrogates=20, ks_bootstrap=0, mixture_restarts=1, fano_windows=(0.5, 1.0, 2.0))
    rows = noise_study(40.86, 100.0, 30.0, [2000.0], [0.0, 2e-5], analysis=o, x_impact_span=30.0, x_impact_noise=[2e-5])
    by = {(r["noise_m"], r["method"]): r for r in rows}
    # the obstacle estimated only at the listed level (measured -3.05 um, sigma 3.21 um: 30 s at 20 um)
    assert "x_impact_err_m" not in by[(0.0, "hysteresis")]
    assert abs(by[(2e-5, "hysteresis")]["x_impact_err_m"]) < 3 * by[(2e-5, "hysteresis")]["x_impact_sigma_m"]
    with pytest.raises(ValueError, match=r"x_impact_noise \[3e-06\] not among"):
        noise_study(40.86, 100.0, 1.0, [2000.0], [0.0], analysis=o, x_impact_noise=[3e-6])
    assert by[(0.0, "hysteresis")]["missed"] == by[(0.0, "hysteresis")]["extra"] == 0
    assert by[(2e-5, "naive threshold")]["extra"] > 0  # noise chatter without hysteresis
    # timing error against the Cramer-Rao bound of the crossing fit (README: 0.65 at 20 um, 2 kHz)
    assert 0.3 < by[(2e-5, "hysteresis")]["timing_crb_ratio"] < 1.5
    assert by[(0.0, "exact events")]["cv2_paper"] == pytest.approx(by[(0.0, "hysteresis")]["cv2_paper"], rel=1e-3)
    _rec, truth = surrogate_record(40.86, 100.0, 30.0, SurrogateOptions(noise=0.0))
    stats = analyse_train(
        ImpactTrain(truth["impacts"]["t"], 100.0, 130.0, omega=40.86, label=LABEL),
        o,
        ("variability", "isi_density", "acf"),
    )
    out = measured_rows(stats, stats, rows, is_surrogate=True, command="x")
    assert len(out) == 5 and all(r["agrees"] == "n.a." for r in out)
    # the obstacle row reports the one level estimated, and no 5-10 um verdict without such a level
    assert "20 um: " in out[4]["replication"] and "At 5-10 um" not in out[4]["replication"]
    assert all("surrogate" in r["replication"] for r in out[:3])
    # the noise row's finding follows the modes counted, not a fixed sentence
    modes = [by[(n, "hysteresis")]["isi_n_modes"] for n in (0.0, 2e-5)]
    assert ("Unimodal from" in out[3]["replication"]) == (min(modes) < 2)
    assert ("Bimodal at every level up to 20 um" in out[3]["replication"]) == (min(modes) >= 2)


def test_cli_reports_estimated_x_impact(tmp_path, capsys):
    rec, _ = surrogate_record(40.86, 100.0, 20.0, SurrogateOptions(rate=2000, noise=2e-6))
    meta = {k: v for k, v in rec.meta.items() if k != "x_impact"}  # the obstacle position unknown
    from impactosc.records.formats import write_record

    write_record(tmp_path / "r.h5", rec.t, rec.x, omega=rec.omega, meta=meta)
    assert main(["extract", str(tmp_path / "r.h5"), "--output", str(tmp_path / "e.h5")]) == 0
    out, err = capsys.readouterr()
    assert "estimated" in out and "fitting the contact law" in err  # said before the fit starts
    _, attrs, _ = read_run(tmp_path / "e.h5")
    # contact-law fit: measured +0.02 um (stated sigma 0.50 um) on this 20 s record at 2 um
    # noise (the curvature estimate it replaced: -8 to -16 um); 3 um bound
    assert abs(attrs["x_impact"] - (-2.086e-3)) < 3e-6
    assert attrs["x_impact_method"] == "contact" and 0 < attrs["x_impact_sigma"] < 1e-6
    # the older estimate on request: the same record, biased low (measured -8 to -16 um)
    argv = ["extract", str(tmp_path / "r.h5"), "--x-impact-method", "curvature", "--output", str(tmp_path / "c.h5")]
    assert main(argv) == 0
    _, attrs_c, _ = read_run(tmp_path / "c.h5")
    assert attrs_c["x_impact_method"] == "curvature" and "curvature" in attrs_c["x_impact_source"]
    assert -25e-6 < attrs_c["x_impact"] - (-2.086e-3) < -3e-6


def test_cli_surrogate_sensor_chain(tmp_path, capsys):
    # the realism options reach the record: the filter's delay is declared in its metadata and
    # extraction subtracts it (events within the timing noise of the unfiltered record's)
    common = ["surrogate", "--omega", "30", "--transient", "50", "--duration", "10", "--noise", "0"]
    assert main([*common, "--output", str(tmp_path / "plain.h5")]) == 0
    filt = ["--lowpass", "300", "--quantum", "1e-7", "--drift", "1e-7", "--clock-jitter", "1e-6"]
    assert main([*common, *filt, "--output", str(tmp_path / "filt.h5")]) == 0
    rec = read_record(tmp_path / "filt.h5")
    assert rec.meta["sensor_delay"] == pytest.approx(butterworth_delay(4, 300.0, 16000.0))
    assert rec.meta["surrogate_quantum_m"] == 1e-7
    for name in ("plain", "filt"):
        assert (
            main(
                ["extract", str(tmp_path / f"{name}.h5"), "--noise", "1e-6", "--output", str(tmp_path / f"{name}_e.h5")]
            )
            == 0
        )
    plain, _, _ = read_run(tmp_path / "plain_e.h5")
    filt_ev, attrs, _ = read_run(tmp_path / "filt_e.h5")
    assert attrs["sensor_delay"] == pytest.approx(rec.meta["sensor_delay"])
    assert filt_ev["impacts"]["t"].size == plain["impacts"]["t"].size > 40  # period 1: 47 in 10 s
    # undelayed, every impact would be 1.39 ms late; corrected, measured within 6.6 us (the
    # filter's shape distorts the fast contact pulse beyond a pure delay); bound 3x that
    assert np.max(np.abs(filt_ev["impacts"]["t"] - plain["impacts"]["t"])) < 2e-5
    # --sensor-delay overrides the record's: 0 leaves every impact late by the filter's delay
    argv = ["extract", str(tmp_path / "filt.h5"), "--noise", "1e-6", "--sensor-delay", "0", "--output"]
    assert main([*argv, str(tmp_path / "late.h5")]) == 0
    late, _, _ = read_run(tmp_path / "late.h5")
    lag = late["impacts"]["t"] - plain["impacts"]["t"]
    assert np.median(lag) == pytest.approx(rec.meta["sensor_delay"], abs=2e-5)
    capsys.readouterr()
    assert main([*common, "--lowpass", "1500", "--output", str(tmp_path / "bad.h5")]) == 2
    assert "lowpass_hz must be below half" in capsys.readouterr().err


def test_h5_record_names_the_sample(tmp_path):
    t = np.arange(500) * 1e-3
    x = -3e-3 + 1e-3 * np.sin(40.0 * t)
    x[123] = np.nan
    with h5py.File(tmp_path / "r.h5", "w") as f:
        f["record/t"], f["record/x"] = t, x
        f.attrs["units"] = "m"
    with pytest.raises(ValueError, match="sample 123: displacement is nan"):
        read_record(tmp_path / "r.h5")


def test_cli_contact_exponent_is_a_number_in_range_or_free(tmp_path, capsys):
    from impactosc.cli.options import contact_exponent

    assert contact_exponent("free") is None and contact_exponent("1.7") == 1.7
    with pytest.raises(SystemExit):
        main(["extract", "r.h5", "--contact-exponent", "3", "--output", str(tmp_path / "e.h5")])
    assert "a contact exponent lies in [1, 2.5]" in capsys.readouterr().err


def test_extract_refuses_too_short_records_in_one_line(tmp_path, capsys):
    from impactosc.cli.main import main

    for body, n in (("", 0), ("0.0,-0.003\n", 1)):
        rec = tmp_path / f"short{n}.csv"
        rec.write_text("# units: m\n# omega: 40.86\nt,x\n" + body)
        assert main(["extract", str(rec), "--output", str(tmp_path / "ev.h5")]) == 2
        err = capsys.readouterr().err.splitlines()
        assert err == [f"impactosc extract: error: {rec}: only {n} samples; a record needs at least 20"]
        assert not (tmp_path / "ev.h5").exists()
