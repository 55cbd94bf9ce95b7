"""The workflow's slow-sweep path: one TDMS record of a slow ramp of w (cart in mm, encoder in
wrapped counts, as a rig writes it), named in config measured.fig02.sweep_record, becomes the
experimental Poincare points of Fig 2 and the figure is drawn from them.

What it guards: the config keys (sweep_record, read, segments, the panel label) reach the
rule, the record is read through the TDMS path, cut by its measured w, and the points are
those of the model's attractor (period 1 on 30-34 rad/s): one tight cluster per segment.
"""

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from impactosc.files import read_provenance
from impactosc.integration.simulate import simulate
from impactosc.measured.surrogate import SurrogateOptions, surrogate_ramp

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIGS = [str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]
COUNTS = 4096
W0, W1, DURATION = 30.0, 34.0, 200.0  # 0.02 rad/s^2: 25 s per 0.5 rad/s bin


def _write_sweep_tdms(path):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    rec, truth = surrogate_ramp(W0, W1, DURATION, SurrogateOptions(rate=2000.0, noise=5e-6), n_initial=300)
    counts = (np.floor(truth["phase"] * COUNTS / (2 * np.pi)).astype(np.int64) % COUNTS).astype(np.int32)
    wf = {"wf_increment": 1.0 / 2000.0, "wf_start_offset": 0.0}
    with TdmsWriter(path) as w:
        w.write_segment(
            [
                RootObject(properties={"label": "rig sweep (test record)"}),
                GroupObject("rig"),
                ChannelObject("rig", "cart", rec.x * 1e3, properties={**wf, "unit_string": "mm"}),
                ChannelObject(
                    "rig", "encoder", counts, properties={**wf, "unit_string": "counts", "counts_per_rev": COUNTS}
                ),
            ]
        )


def test_sweep_record_becomes_the_fig02_panel(tmp_path):
    sweep = tmp_path / "sweep.tdms"
    _write_sweep_tdms(sweep)
    extra = tmp_path / "sweep.yaml"
    extra.write_text(
        "measured:\n"
        f"  fig02:\n    sweep_record: {sweep}\n"
        "    read: {group: rig, channel: cart, phase_channel: encoder}\n"
        "    segments: {bin_width: 0.5, settle: 5.0, min_points: 20}\n"
        "bifurcation:\n  fig02:\n    experimental: {label: rig sweep (test record)}\n"
    )
    points = "results/runs/measured/fig02_experimental.h5"
    run = subprocess.run(
        [
            *SNAKEMAKE,
            points,
            "fig02",
            "-d",
            str(tmp_path),
            "--configfile",
            *CONFIGS,
            str(extra),
            "-j2",
            "--quiet",
            "rules",
        ],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, f"sweep-record workflow failed:\n{run.stdout[-4000:]}\n{run.stderr[-4000:]}"
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
    assert (tmp_path / "results" / "figures" / "fig02.png").exists()
