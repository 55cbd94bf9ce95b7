"""Every located bifurcation point of the continued orbits beside the sweeps' readings (rule orbits).

Reads input.segments (named by params.names) and input.transitions (the sweeps' transitions CSV); writes
output.csv, output.md (the table) and output.rows (the refined paper rows).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("orbits")
configure_logging(snakemake)

import logging

from impactosc.dynamics.orbit_table import bifurcation_table, cascade_chain, chain_ratios, multipliers_text
from impactosc.io.files import read_csv, read_json, write_csv, write_text
from impactosc_study.paper.rows.bifurcation import orbit_rows
from impactosc_study.paper.table import to_markdown, write_rows


def period1_grazings(segments):
    """Located grazings of period-1 orbits, multipliers on the near-miss side and past it."""
    out = []
    for seg in segments.values():
        for p in seg["special_points"]:
            if p["kind"] == "grazing" and p["located"] and p["n_periods"] == 1:
                sides = [(p["impacts"][0], p["w_before"], p["mu_before_re"], p["mu_before_im"]),
                         (p["impacts"][1], p["w_after"], p["mu_after_re"], p["mu_after_im"])]  # fmt: skip
                near_miss, past = sorted(sides, key=lambda s: s[0])
                out.append({"omega": p["omega"], "impacts": p["impacts"],
                            "mu_before": f"{multipliers_text(*near_miss[2:])} at w = {near_miss[1]:.4f}",
                            "mu_after": f"{multipliers_text(*past[2:])} at w = {past[1]:.4f}"})  # fmt: skip
    return out


def main(inp, params, out):
    segments = {name: read_json(path) for name, path in zip(params.names, inp.segments)}
    rows = bifurcation_table(segments, read_csv(inp.transitions))
    write_csv(out.csv, rows, sources=[*inp.segments, inp.transitions])
    chain = cascade_chain(segments)
    ratios = chain_ratios(chain)
    cost = ", ".join(f"{n} {s['cpu_seconds']:.0f} s ({len(s['points'])} orbits)" for n, s in segments.items())
    write_text(
        out.md,
        "# Bifurcation points of the continued orbits\n\n"
        "Each located on the orbits (period doubling: det(M + I) bisected to 1e-9 rad/s; fold: the branch's "
        "turning point; grazing: the smallest near-miss gap through zero), beside what the brute-force sweeps "
        "read. No Neimark-Sacker point can occur: det M <= exp(-c N 2 pi / (m w)) < 1 on every orbit "
        "(Liouville), checked at every continued point.\n\n"
        + to_markdown(rows, list(rows[0]) if rows else [])
        + "\n\nPeriod-doubling cascade: "
        + (", ".join(f"{p['omega']:.10f}" for p in chain) or "none")
        + " rad/s; ratios of successive intervals: "
        + (", ".join(f"{r:.3f}" for r in ratios) or "too few doublings")
        + " (Feigenbaum 4.669).\n\nCost (CPU time per segment job): "
        + cost
        + ".\n",
    )
    worst = max(p["det"] / p["det_bound"] for s in segments.values() for p in s["points"])
    logging.info("%d bifurcation points; largest det M / Liouville bound %.3g", len(rows), worst)
    if worst > 1 + 1e-6:
        raise RuntimeError(f"det M exceeds Liouville's bound by a factor {worst:.6g}: the monodromy is wrong somewhere")
    write_rows(out.rows, orbit_rows(chain, ratios, period1_grazings(segments), params.command), sources=inp.segments)


main(snakemake.input, snakemake.params, snakemake.output)
