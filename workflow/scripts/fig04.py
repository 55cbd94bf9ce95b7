"""Fig 4: phase portraits before (23.05, branch) and after (23.03) the grazing, and the spectrum.

Reads input.before, input.after (run files with trajectory windows), input.spectrum (Fig 4c), input.stats
and input.before_stats (inset notes); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig04")
configure_logging(snakemake)

import json
import logging

from impactosc.io.files import read_run
from impactosc_study.figures import save_figure
from impactosc_study.figures.periodic import fig04_grazing_portraits

with open(snakemake.input.spectrum) as f:
    spectrum = json.load(f)
with open(snakemake.input.stats) as f:
    stats = json.load(f)
with open(snakemake.input.before_stats) as f:
    stats.update(json.load(f))
panels = {}
for key, path, tag, sk in (
    ("before", snakemake.input.before, "(branch, before grazing)", "before_grazing_branch"),
    ("after", snakemake.input.after, "(after grazing)", "after_grazing"),
):
    _, attrs, traj = read_run(path)
    s = stats[sk]
    box = snakemake.params.inset
    note = (
        f"inset: near miss {s['min_gap'] * 1e6:.2f} $\\mu$m below $x_I$"
        if key == "before"
        else f"inset: slowest impact, {s['min_impact_v'] * 1e3:.1f} mm/s at $x_I$"
    )
    panels[key] = {
        "omega": attrs["omega"],
        "x": traj["x"],
        "v": traj["v"],
        "tag": tag,
        "note": note,
        "inset": ((attrs["param_xI"] + box["dx"][0], attrs["param_xI"] + box["dx"][1]), tuple(box["v"])),
    }
fig = fig04_grazing_portraits(panels["before"], panels["after"], spectrum, attrs["param_xI"])
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"wrote {snakemake.output.png} and {snakemake.output.pdf}")
