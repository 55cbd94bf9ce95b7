"""Read the bifurcation diagrams: periods, transitions, grazing, hysteresis, paper rows.

Reads input.sweeps (named by params.names) and input.grazing (results/stats/periodic/grazing.json); writes
output.per_w, output.segments, output.transitions (CSV), output.stats (JSON digest), output.rows.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_tables", law="bc")
configure_logging(snakemake)

import logging

from impactosc.dynamics.diagram import differing_windows, read_sweep
from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json, write_csv, write_json
from impactosc_study.paper.rows.bifurcation import bifurcation_rows as paper_rows
from impactosc_study.paper.table import write_rows

# Float cells as Python prints them (shortest round-trip form), as these tables always were:
# their w values are already rounded to 6 decimals by the reading, so no further rounding.
FLOATS = ""


def main(inp, params, out):
    r = params.reading
    readings = {}
    for name, path in zip(params.names, inp.sweeps):
        readings[name] = read_sweep(
            load_sweep(path)[0],
            name,
            x_tol=r["x_tol"],
            v_tol=r["v_tol"],
            isi_tol=r["isi_tol"],
            min_points=r["min_points"],
            n_fit=r["n_fit"],
        )
        logging.info(
            "%s: %d segments, %d transitions, %d grazings, %d abandoned w",
            name,
            len(readings[name].segments),
            len(readings[name].transitions),
            len(readings[name].grazings),
            len(readings[name].failed_omegas),
        )
    per_w = [{"sweep": n, **row} for n, rd in readings.items() for row in rd.table.rows()]
    write_csv(out.per_w, per_w, list(per_w[0]), floats=FLOATS, sources=inp.sweeps)
    segs = [{"sweep": n, **s.to_dict()} for n, rd in readings.items() for s in rd.segments]
    write_csv(out.segments, segs, list(segs[0]), floats=FLOATS, sources=inp.sweeps)
    summaries = {n: rd.summary() for n, rd in readings.items()}
    trans = [{"sweep": n, **t} for n, s in summaries.items() for t in s["transitions"]]
    a, b = params.overlay
    windows = differing_windows(readings[a].table, readings[b].table, r["min_points"])
    for lo, hi in windows:
        trans.append(
            {
                "sweep": f"{a} vs {b}",
                "kind": "directions differ",
                "omega_before": lo,
                "omega_after": hi,
                "before": a,
                "after": b,
                "detail": "different attractors (hysteresis)",
                "grazing_omega_zero": "",
                "omega": round(0.5 * (lo + hi), 6),
                "width": round(hi - lo, 6),
                "is_grazing": False,
            }
        )
    columns = [
        "sweep",
        "kind",
        "omega",
        "width",
        "omega_before",
        "omega_after",
        "before",
        "after",
        "detail",
        "is_grazing",
        "grazing_omega_zero",
    ]
    write_csv(out.transitions, [{k: t[k] for k in columns} for t in trans], columns, floats=FLOATS, sources=inp.sweeps)
    reference = None
    if inp.get("grazing"):
        reference = read_json(inp.grazing)
    rows = paper_rows(readings[params.fig03b], params.command, reference_grazing=reference)
    write_rows(out.rows, rows, sources=inp)
    ref = None
    if reference:
        ref = {
            "omega_g": reference["omega_g"],
            "omega_miss": reference["bracket"]["omega_miss"],
            "omega_contact": reference["bracket"]["omega_contact"],
        }
    stats = {"sweeps": summaries, "directions_differ": {"sweeps": [a, b], "windows": windows}, "reference_grazing": ref}
    write_json(out.stats, stats, sources=inp)
    logging.info("%d paper rows, %d hysteresis windows", len(rows), len(windows))


main(snakemake.input, snakemake.params, snakemake.output)
