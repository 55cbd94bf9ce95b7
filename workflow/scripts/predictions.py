"""The predicted points of every segment with their standard errors (rule predictions).

Reads input.segments (rule prediction_segment, named by params.names) and params.model_source; writes
output.csv and output.md.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("predictions")
configure_logging(snakemake)

import logging

from impactosc.identification.predictions import points_markdown
from impactosc.io.files import read_json, write_csv, write_text


def main(inp, params, out):
    rows = []
    for name, path in zip(params.names, inp.segments):
        found = read_json(path)
        rows += [{"segment": name, **{k: v for k, v in p.items() if k != "segment"}} for p in found["points"]]
    columns = ["segment", "kind", "omega", "n_periods", "se", "note"]
    columns += sorted({k for r in rows for k in r if k.startswith("d_")})
    write_csv(out.csv, [{c: r.get(c, "") for c in columns} for r in rows], sources=list(inp.segments))
    write_text(
        out.md,
        points_markdown(
            rows,
            title=f"Predicted bifurcation points of {params.model_source['description']}",
            description="Each point located on its continued segment (table of the orbits group) and its "
            "standard error from the model file's covariance: delta method over the point's sensitivities, "
            "by implicit differentiation of its defining equation (impactosc.dynamics.point_sensitivity). "
            "The Monte Carlo check of these standard errors: target prediction_check.",
        ),
    )
    logging.info("%d points of %d segments", len(rows), len(params.names))


main(snakemake.input, snakemake.params, snakemake.output)
