"""The restitution table and figure of the contact laws (rule restitution).

Reads input.cache, params.model (its m, kI, n1), params.e, params.v0_table, params.v0, params.e_v0;
writes output.table (CSV: law, e, v0, e_eff), output.md (with each law's verdict), output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("restitution")
configure_logging(snakemake)

import logging

from impactosc.dynamics.restitution import delivers, restitution_rows
from impactosc.io.files import write_csv, write_text
from impactosc.model.parameters import ModelParams
from impactosc_study.figures import save_figure
from impactosc_study.figures.restitution import restitution_figure

COLUMNS = ["law", "e", "v0", "e_eff", "difference"]
#: a law delivers its nominal e where a free impact's e_eff lies within this of it
TOLERANCE = 0.05


def markdown(by_e, verdicts, v0) -> str:
    laws = list(verdicts)
    lines = [
        "# Effective restitution of a free impact, by contact law",
        "",
        f"-v_exit / v0 of one free impact at v0 = {v0:g} m/s (no spring, forcing or friction), by the core "
        "(impactosc.dynamics.restitution). A law delivers its nominal e where e_eff lies within "
        f"{TOLERANCE:g} of it.",
        "",
        "| nominal e | " + " | ".join(laws) + " |",
        "|---|" + "---|" * len(laws),
    ]
    for e in sorted({r["e"] for r in by_e}):
        cells = [next(f"{r['e_eff']:.4f}" for r in by_e if r["law"] == law and r["e"] == e) for law in laws]
        lines.append(f"| {e:g} | " + " | ".join(cells) + " |")
    lines += ["", "| law | delivers e within 0.05 at | largest \\|e_eff - e\\| |", "|---|---|---|"]
    for law, v in verdicts.items():
        within = ", ".join(f"{e:g}" for e in v["within"]) or "none of these"
        lines.append(f"| {law} | {within} | {v['worst']:.3f} |")
    return "\n".join(lines) + "\n"


def main(params, out):
    model = ModelParams(**params.model)
    by_e = restitution_rows(model, params.e, [params.v0_table])
    by_v0 = restitution_rows(model, [params.e_v0], params.v0)
    verdicts = delivers(by_e, TOLERANCE)
    write_csv(out.table, by_e + by_v0, COLUMNS)
    write_text(out.md, markdown(by_e, verdicts, params.v0_table))
    save_figure(restitution_figure(by_e, by_v0), out.png, out.pdf)
    for law, v in verdicts.items():
        logging.info("%s: within %g of e at %s; worst %.3f", law, TOLERANCE, v["within"], v["worst"])


main(snakemake.params, snakemake.output)
