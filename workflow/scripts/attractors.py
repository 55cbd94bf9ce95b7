"""Join the attractors along w, follow them from w to w, and say why Figs 2 and 3b differ.

Reads input.parts (groups of w, in order) and input.sweeps; writes output.surveys (joined HDF5), output.along_w,
output.events, output.hysteresis (CSV: fractions per w, births and deaths, the sweeps' differences), output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("attractors")
configure_logging(snakemake)

import logging

import h5py

from impactosc.dynamics.attractor_continuation import (
    hysteresis_rows,
    load_surveys,
    save_surveys,
    study_omegas,
    track,
)
from impactosc.dynamics.attractor_survey import survey_rows
from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import write_csv
from impactosc.model.parameters import ModelParams
from impactosc_study.figures import save_figure
from impactosc_study.figures.attractors import attractors_figure

ALONG_W = ["omega", "track", "name", "kind", "period", "impacts", "exponent", "cells", "fraction", "se",
           "median_iterations", "basin_entropy", "boundary_basin_entropy", "boundary_fraction"]  # fmt: skip
HYSTERESIS = ["omega", "omega_decreasing", "increasing_reads", "decreasing_reads", "attractors", "found",
              "increasing", "decreasing", "why", "explained"]  # fmt: skip


def main(inp, params, out):
    parts = [inp.parts] if isinstance(inp.parts, str) else list(inp.parts)
    surveys = [s for p in parts for s in load_surveys(p)]
    with h5py.File(parts[0], "r") as f:
        total, cpu_attrs = (
            int(f.attrs["n_omegas_total"]),
            {k: f.attrs[k] for k in f.attrs if k.startswith("recurrence_")},
        )
    increasing, decreasing = (load_sweep(path)[0] for path in inp.sweeps)
    omegas, differing = study_omegas(increasing, decreasing, params.reading, params.attractors["omega"])
    if len(surveys) != total or [round(s.omega, 9) for s in surveys] != [round(w, 9) for w in omegas]:
        raise ValueError(f"the parts hold {len(surveys)} w values, the config and sweeps ask for {omegas.size}")
    tracks = track(surveys)
    along = []
    for s, ids in zip(surveys, tracks.ids):
        e = s.entropy
        for r in survey_rows(s):
            if r["class"] <= 0 and not r["cells"]:
                continue
            track_id = ids[r["class"] - 1] if r["class"] > 0 else ""
            r = {k: v for k, v in r.items() if k in ALONG_W}
            mixing = {"basin_entropy": e.entropy, "boundary_basin_entropy": e.boundary_entropy,
                      "boundary_fraction": e.boundary_fraction} if e else {}  # fmt: skip
            along.append({**r, "omega": s.omega, "track": track_id, **mixing})
    write_csv(out.along_w, along, ALONG_W, sources=parts)
    write_csv(out.events, tracks.events, ["omega", "event", "track", "into"], sources=parts)
    rows = hysteresis_rows(surveys, tracks, increasing, decreasing, differing, ModelParams(**params.model))
    write_csv(out.hysteresis, rows, HYSTERESIS, yes_no=True, sources=[*parts, *inp.sweeps])
    save_surveys(out.surveys, surveys, sources=parts, **cpu_attrs)
    fig = attractors_figure(surveys, tracks.ids, [d[0] for d in differing])
    save_figure(fig, out.png, out.pdf)
    explained = sum(r["explained"] for r in rows)
    cpu = sum(s.cpu_time for s in surveys)
    logging.info("%d w, %d tracks, %d events; %.0f CPU s in the surveys", len(surveys),
                 len({t for ids in tracks.ids for t in ids}), len(tracks.events), cpu)  # fmt: skip
    logging.info("the sweeps differ at %d w: %d explained by coexisting attractors", len(rows), explained)
    for why in sorted({r["why"] for r in rows}):
        logging.info("%s: %s", why, ", ".join(f"{r['omega']:.3f}" for r in rows if r["why"] == why))
    for r in rows:
        if not r["explained"]:
            logging.info("%.3f / %.3f (%s): up %s | down %s | found %s", r["omega"], r["omega_decreasing"], r["why"],
                         r["increasing"], r["decreasing"], r["found"])  # fmt: skip


main(snakemake.input, snakemake.params, snakemake.output)
