"""Fig 3: (a) construction of the impact map on x(t), (b) the ISI bifurcation diagram.

Reads input.run (run file with a trajectory window), input.sweeps (the decreasing sweep) and input.stats
(its reading); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig03")
configure_logging(snakemake)

import json
import logging
from pathlib import Path

import matplotlib.pyplot as plt

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_run
from impactosc_study.figures import apply_style, save_figure
from impactosc_study.figures.bifurcation import fig03b_arguments, fig03b_isi
from impactosc_study.figures.periodic import fig03a_impact_construction
from impactosc_study.figures.style import DOUBLE


def main(inp, params, out):
    apply_style()
    events, attrs, traj = read_run(inp.run)
    if traj is None:
        raise ValueError(f"{inp.run} has no trajectory window; Fig 3a needs x(t)")
    res, sweep_attrs = load_sweep(inp.sweeps[0])
    stats = json.loads(Path(inp.stats).read_text())
    summary = stats["sweeps"][params.sweep]
    fig = plt.figure(figsize=(DOUBLE, DOUBLE * 0.62))
    grid = fig.add_gridspec(2, 2, width_ratios=[2.2, 1], height_ratios=[1, 1.15])
    ax_a = fig.add_subplot(grid[0, :])
    fig03a_impact_construction(
        traj["t"], traj["x"], events["impacts"]["t"], attrs["param_xI"], params.start, params.span, ax=ax_a
    )
    ax_a.set_title(
        r"(a) impact moments $T_j$ and intervals $S_j$ at $\omega$ = " + f"{attrs['omega']:g} rad/s", loc="left"
    )
    w, s, kw = fig03b_arguments(res, sweep_attrs, summary, params.zoom_near, params.zoom_half_width)
    axes_b = [fig.add_subplot(grid[1, 0])] + ([fig.add_subplot(grid[1, 1])] if kw["zoom"] else [])
    fig03b_isi(w, s, axes=axes_b, **kw)
    axes_b[0].set_title("")  # replaced by the panel label on the left
    axes_b[0].set_title(r"(b) inter-impact intervals, decreasing $\omega$", loc="left")
    save_figure(fig, out.png, out.pdf)
    logging.info(f"wrote {out.png} and {out.pdf}")


main(snakemake.input, snakemake.params, snakemake.output)
