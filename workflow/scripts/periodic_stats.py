"""Section 2.1 numbers, attractor summaries and spectra of run files (Figs 4, 5, table rows).

Reads every snakemake.input (run files; the input names become the keys of the output) and
snakemake.params.spectrum (peak-finder options); writes snakemake.output.stats (JSON of
impactosc.statistics.periodic_train.run_summary per input) and, when params.spectrum_of names an input,
snakemake.output.spectrum (its spectrum of x with lines and labels, JSON; Fig 4c).
"""

from _logging import configure_logging

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
