"""The laws study's models: the study's model with each contact law, a restitution law's e matched to its dissipation.

Reads input.cache, params.model, params.model_source, params.laws, params.v0; writes output.table (CSV: law, e,
e_eff at v0, the model's e_eff), output.md, output.models (one model file per law, in the order of params.laws).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("laws_models")
configure_logging(snakemake)

import logging

from impactosc.dynamics.restitution import matched_models
from impactosc.io.files import write_csv, write_text
from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import ModelParams

COLUMNS = ["law", "e", "v0", "e_eff", "reference_e_eff"]


def markdown(rows, v0, source) -> str:
    lines = [
        "# The laws study: each contact law's e, matched to the model's dissipation",
        "",
        f"The model ({source}) with each contact law in place of its own. A restitution law's nominal e "
        f"is the root of e_eff(e) = the model's e_eff at v0 = {v0:g} m/s: e_eff = -v_exit / v0 of one free "
        "impact (no spring, forcing or friction), by the core (impactosc.dynamics.restitution). A law "
        "without e (bc, hertz) takes the model's own numbers; hertz dissipates nothing at the contact.",
        "",
        f"| law | e | e_eff at {v0:g} m/s | the model's e_eff |",
        "|---|---|---|---|",
    ]
    for r in rows:
        e = "-" if r["e"] is None else f"{r['e']:.6f}"
        lines.append(f"| {r['law']} | {e} | {r['e_eff']:.6f} | {r['reference_e_eff']:.6f} |")
    return "\n".join(lines) + "\n"


def main(params, out):
    matched = matched_models(ModelParams(**params.model), params.laws, params.v0)
    rows = [
        {"law": m["law"], "e": m["e"], "v0": params.v0, "e_eff": m["e_eff"], "reference_e_eff": m["reference"]}
        for m in matched
    ]
    for m, path in zip(matched, out.models):
        write_model_file(path, m["params"], name=f"{params.model_source['description']}, contact law {m['law']}")
    write_csv(out.table, rows, COLUMNS, floats=".10g")
    write_text(out.md, markdown(rows, params.v0, params.model_source["description"]))
    for r in rows:
        logging.info("%s: e = %s, e_eff = %.6f (the model's %.6f)", r["law"], r["e"], r["e_eff"], r["reference_e_eff"])


main(snakemake.params, snakemake.output)
