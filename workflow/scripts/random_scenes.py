"""Merge the parts of the randomized differential test of the core.

Reads input.parts (CSV rows of random_scenes_part); writes output.csv (all scenes, in scene order) and
output.md (the summary the README quotes).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("random_scenes")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_csv, write_csv, write_text
from impactosc_bench.random_scenes import BOUND, BOUND_X, summarise_scenes

rows = [r for path in snakemake.input.parts for r in read_csv(path, numbers=True)]
for r in rows:
    r["scene"], r["compared"] = int(r["scene"]), int(r["compared"])
rows.sort(key=lambda r: r["scene"])
s = summarise_scenes(rows)
logging.info("summary: %s", s)
write_csv(snakemake.output.csv, rows, floats="", sources=snakemake.input.parts)
rs = snakemake.params.rs
lines = [
    "# Randomized scenes: the core against SciPy (LSODA, two tolerances)",
    "",
    f"Seed {rs['seed']}, {s['scenes']} scenes of {rs['horizon']:g} s, core rtol {rs['rtol']:g}; "
    f"bound {BOUND:g} s on impact times (or {BOUND_X:g} m of position, |dt| v, for slow impacts) over the "
    "horizon where the two references agree.",
    "",
    "| scenes | mean horizon (s) | impacts compared | worst difference (s) | stalls | failures | no reference |",
    "|---|---|---|---|---|---|---|",
    f"| {s['scenes']} | {s['mean_horizon_s']:.3g} | {s['impacts_compared']} | {s['worst_dt_s']:.2g} | {s['stalls']} "
    f"| {s['failures']} | {s['no_reference']} |",
    "",
]
bad = [r for r in rows if r["status"] != "ok"]
if bad:
    lines += ["Scenes not ok:", ""] + [f"- scene {r['scene']}: {r['status']}: {r['message']}" for r in bad]
write_text(snakemake.output.md, "\n".join(lines) + "\n")
