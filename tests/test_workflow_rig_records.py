"""The workflow's measured-record routes with rig files (TDMS: cart in mm, encoder in wrapped
counts, time as waveform properties, as NI software writes them), on config/tiny.yaml:

* a slow ramp of w named in config measured.fig02.sweep_record becomes the experimental
  Poincare points of Fig 2 (the points of the model's period-1 branch, one line per segment),
  and the figure is drawn from them;
* a chaotic record named in measured.chaos.record, without the obstacle position, becomes the
  second impact train of Figs 8-10: xI estimated by the contact fit, impacts as the truth's.

What it guards: the config keys (record, sweep_record, read, segments, the panel labels) reach
the rules, and the records go through the TDMS reader, not only the CSV/HDF5 ones.

Both builds (about 35 s of a worker) run with the slow tests. The default run keeps a dry run of
both routes (each record is the input of the job that reads it); the TDMS reader is tested in
tests/test_tdms_records.py, the workflow end to end in tests/test_workflow_tiny.py.
"""

import dataclasses
import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.io.files import read_provenance, read_run
from impactosc.records.surrogate import SurrogateOptions, surrogate_ramp, surrogate_record

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIGS = [str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]
COUNTS = 4096
W0, W1, DURATION = 30.0, 34.0, 200.0  # 0.02 rad/s^2: 25 s per 0.5 rad/s bin


def _write_tdms(path, rec, phase=None, label="rig record (test)"):
    """rec's x as channel rig/cart in mm, its phase (if given) as rig/encoder in wrapped counts."""
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    wf = {"wf_increment": float(rec.t[1] - rec.t[0]), "wf_start_offset": float(rec.t[0])}
    channels = [ChannelObject("rig", "cart", rec.x * 1e3, properties={**wf, "unit_string": "mm"})]
    if phase is not None:
        counts = (np.floor(phase * COUNTS / (2 * np.pi)).astype(np.int64) % COUNTS).astype(np.int32)
        props = {**wf, "unit_string": "counts", "counts_per_rev": COUNTS}
        channels.append(ChannelObject("rig", "encoder", counts, properties=props))
    root = {"label": label} if rec.omega is None else {"label": label, "omega": rec.omega}
    with TdmsWriter(path) as w:
        w.write_segment([RootObject(properties=root), GroupObject("rig"), *channels])


def _run(tmp_path, extra_config: str, *targets, dry_run=False):
    extra = tmp_path / "extra.yaml"
    extra.write_text(extra_config)
    quiet = ["-n"] if dry_run else ["-j2", "--quiet", "rules"]
    run = subprocess.run(
        [*SNAKEMAKE, *targets, "-d", str(tmp_path), "--configfile", *CONFIGS, str(extra), *quiet],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, f"workflow failed:\n{run.stdout[-4000:]}\n{run.stderr[-4000:]}"
    return run.stdout + run.stderr


def test_records_named_in_the_config_are_the_inputs_of_their_jobs(tmp_path):
    """A dry run (the default run's cheap check of the two routes below): the job writing the Fig 2
    points reads the sweep record, the job writing the second train's events the chaotic record."""
    sweep, chaos = tmp_path / "sweep.tdms", tmp_path / "chaos.tdms"
    sweep.touch()
    chaos.touch()
    points = "results/paper/runs/measured/fig02_experimental.h5"
    events = "results/paper/runs/measured/chaos_events.h5"
    plan = _run(
        tmp_path,
        f"measured:\n  fig02:\n    sweep_record: {sweep}\n"
        "    read: {group: rig, channel: cart, phase_channel: encoder}\n"
        "    label: rig sweep (test record)\n"
        f"  chaos:\n    record: {chaos}\n    read: {{group: rig, channel: cart}}\n"
        "    label: rig chaos (test record)\n",
        points,
        events,
        dry_run=True,
    )
    inputs = {}  # output -> inputs of the job that writes it
    for block in re.split(r"^(?:local)?rule \w+:$", plan, flags=re.M)[1:]:
        output = re.search(r"^    output: (.*)$", block, re.M)
        read = re.search(r"^    input: (.*)$", block, re.M)
        for path in output[1].split(", ") if output else []:
            inputs[path] = read[1].split(", ") if read else []
    assert str(sweep) in inputs.get(points, []), plan[-3000:]
    assert str(chaos) in inputs.get(events, []), plan[-3000:]


@pytest.mark.slow
def test_sweep_record_becomes_the_fig02_panel(tmp_path):
    sweep = tmp_path / "sweep.tdms"
    rec, truth = surrogate_ramp(W0, W1, DURATION, SurrogateOptions(rate=2000.0, noise=5e-6), n_initial=300)
    _write_tdms(sweep, dataclasses.replace(rec, omega=None), truth["phase"], label="rig sweep (test record)")
    points = "results/paper/runs/measured/fig02_experimental.h5"
    _run(
        tmp_path,
        "measured:\n"
        f"  fig02:\n    sweep_record: {sweep}\n"
        "    read: {group: rig, channel: cart, phase_channel: encoder}\n"
        "    segments: {bin_width: 0.5, settle: 5.0, min_points: 20}\n"
        "    label: rig sweep (test record)\n",
        points,
        "fig02",
    )
    with h5py.File(tmp_path / points) as f:
        seg_w = f["record_omega"][()]
        omega, x, point_w = f["omega"][()], f["x"][()], f["point_omega"][()]
        assert f.attrs["label"] == "rig sweep (test record)"
    assert str(sweep) in str(read_provenance(tmp_path / points)["sources"])
    # bins of 0.5 rad/s centred on multiples of it over 30..34: the inner ones all kept
    assert seg_w.size >= 7 and seg_w.min() < 30.6 and seg_w.max() > 33.4
    for w in np.unique(omega):
        inside = omega == w
        xs, ws = x[inside], point_w[inside]
        # period 1: the points of a segment lie on one line x(w) (the branch's slope across the
        # segment's measured w) up to the sensor noise
        line = np.polyfit(ws - w, xs, 1)
        resid = xs - np.polyval(line, ws - w)
        # ... and on the model's period-1 attractor at the segment's w (quasi-static lag)
        model = simulate(w, 300 * 2 * np.pi / w, 2 * np.pi / w, record=("poincare",)).events["poincare"]["x"][0]
        # measured: residual std 2.3-3.1 um (5 um sensor noise), offset -1.6 to -6.5 um; bounds ~2x
        assert xs.size >= 20 and np.std(resid) < 6e-6, (w, np.std(resid))
        assert abs(line[1] - model) < 1.5e-5, (w, line[1] - model)
    assert (tmp_path / "results" / "paper" / "figures" / "fig02.png").exists()


@pytest.mark.slow
def test_chaos_record_becomes_the_second_train(tmp_path):
    # 40 s of the chaotic attractor, 5 um noise, no x_impact in the file: estimated
    rec, truth = surrogate_record(40.86, 100.0, 40.0, SurrogateOptions(rate=2000.0, noise=5e-6))
    chaos = tmp_path / "chaos.tdms"
    _write_tdms(chaos, rec, label="rig chaos (test record)")
    events = "results/paper/runs/measured/chaos_events.h5"
    _run(
        tmp_path,
        f"measured:\n  chaos:\n    record: {chaos}\n    read: {{group: rig, channel: cart}}\n"
        "    label: rig chaos (test record)\n",
        events,
        "fig09",
    )
    ev, attrs, _ = read_run(tmp_path / events)
    # the contact fit on 40 s at 5 um: sigma about 0.8 um; within 3 um and 3 sigma
    assert attrs["x_impact_method"] == "contact"
    err = attrs["x_impact"] - rec.meta["x_impact"]
    assert abs(err) < min(3e-6, 3 * attrs["x_impact_sigma"]), (err, attrs["x_impact_sigma"])
    # every true impact found once (5 um noise: none missed in the noise study), times within 1 ms
    t_true = truth["impacts"]["t"]
    assert ev["impacts"]["t"].size == t_true.size
    assert np.max(np.abs(ev["impacts"]["t"] - t_true)) < 1e-3
    assert attrs["omega"] == pytest.approx(40.86)
    assert (tmp_path / "results" / "paper" / "figures" / "fig09.png").exists()
