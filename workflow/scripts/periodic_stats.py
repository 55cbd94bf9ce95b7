"""Attractor summaries and spectra of the period-4 and before-grazing scenes, section 2.1.

Reads every input: run files (input.after_grazing, input.before_grazing_from_rest), named as the output's
keys; writes output.stats (JSON) and, with params.spectrum_of, output.spectrum (Fig 4c).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("periodic_stats")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_json
from impactosc.statistics.periodic_train import run_summary

opts = snakemake.params.spectrum
spectrum_of = snakemake.params.get("spectrum_of")
stats, spectra = {}, {}
for name, path in snakemake.input.items():
    stats[name], spectra[name] = run_summary(path, opts)
write_json(snakemake.output.stats, stats, final_newline=True, sources=snakemake.input)
if spectrum_of:
    write_json(
        snakemake.output.spectrum,
        spectra[spectrum_of].to_dict(),
        final_newline=True,
        sources=dict(snakemake.input.items())[spectrum_of],
    )
logging.info(f"wrote {', '.join(map(str, snakemake.output))}")
