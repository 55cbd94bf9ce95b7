"""Join the largest exponent's sweep parts and set its sign against each sweep's periods.

Reads input.parts (per sweep, chunks in order), input.per_w, input.transitions (the sweeps' reading) and
input.orbits (the continued segments); writes output.lambdas (one CSV per sweep), output.signs (Markdown).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("lyapunov_sweeps")
configure_logging(snakemake)

import logging

from impactosc.dynamics.lyapunov_reading import sign_agreement, summarise_agreement
from impactosc.io.files import read_csv, read_json, write_csv, write_text


def main(inp, params, out):
    per_w, transitions = read_csv(inp.per_w, numbers=True), read_csv(inp.transitions, numbers=True)
    located = [p["omega"] for f in inp.orbits for p in read_json(f)["special_points"] if p["located"]]
    parts = list(inp.parts)
    lines = [
        "# The largest Lyapunov exponent against the period each sweep detected",
        "",
        "lambda1 < 0 should go with a periodic w (period >= 1) and lambda1 > 0 with a non-periodic one; a "
        "disagreement within one grid step of a transition is expected (lambda1 passes through zero at a "
        "bifurcation, and neither a finite run nor the reading is settled there). Transitions: those of the sweep's "
        "reading and the bifurcations located on the continued orbits (results/<study>/tables/orbits/).",
        "",
        "| sweep | w values | agrees | near a transition | disagrees | no exponent | disagrees at w (rad/s) |",
        "|---|---|---|---|---|---|---|",
    ]
    details = []
    for k, name in enumerate(params.names):
        rows = [r for p in parts[k * params.chunks : (k + 1) * params.chunks] for r in read_csv(p, numbers=True)]
        write_csv(out.lambdas[k], rows, floats=".8g", sources=parts)
        lam = {round(float(r["omega"]), 6): float(r["lambda1_per_period"]) for r in rows}
        verdicts = sign_agreement(
            [r for r in per_w if r["sweep"] == name],
            lam,
            [float(t["omega"]) for t in transitions if t["sweep"] == name] + located,
            abs(params.grids[name]["step"]),
        )
        summary = summarise_agreement(verdicts)
        c = summary["counts"]
        at = ", ".join(f"{w:g}" for w in summary["disagree_at"]) or "-"
        lines.append(
            f"| {name} | {len(verdicts)} | {c.get('agrees', 0)} | {c.get('near a transition', 0)} "
            f"| {c.get('disagrees', 0)} | {c.get('no exponent', 0)} | {at} |"
        )
        logging.info("%s: %s", name, c)
        ts = [float(t["omega"]) for t in transitions if t["sweep"] == name] + located
        for r in verdicts:
            if r["verdict"] == "disagrees":
                near = min(ts, key=lambda t: abs(t - r["omega"])) if ts else float("nan")
                read = f"period {r['period']}" if r["period"] else "non-periodic"
                details.append(f"| {name} | {r['omega']:g} | {read} | {r['lambda1_per_period']:+.4f} | {near:g} |")
    if details:
        lines += [
            "",
            "Each disagreement: the reading, lambda1 per period, and the nearest transition of the reading. A "
            "non-periodic reading with lambda1 < 0 is a periodic orbit the reading missed (a transient not decayed "
            "in its 200 periods near a doubling, or a period beyond what it detects); |lambda1| of a few 1e-3 is a "
            "bifurcation that the reading places elsewhere.",
            "",
            "| sweep | w (rad/s) | reading | lambda1 | nearest transition (rad/s) |",
            "|---|---|---|---|---|",
            *details,
        ]
    write_text(out.signs, "\n".join(lines) + "\n")


main(snakemake.input, snakemake.params, snakemake.output)
