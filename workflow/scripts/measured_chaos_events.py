"""Extract impact events from one record (measured or surrogate).

Reads input.kernels (compiled kernels), input.record (impactosc.records.formats format), params.x_impact,
params.noise (None: from the metadata, or estimated) and params.reader (a TDMS record's channels); writes
output.events (a run file).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_chaos_events")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_run
from impactosc.records.extract import ExtractOptions, extract_events
from impactosc.records.streams import open_record_stream

p = snakemake.params
with open_record_stream(snakemake.input.record, **p.reader) as rec:  # read in chunks: any length
    events, attrs = extract_events(rec, p.x_impact, ExtractOptions(noise=p.noise))
write_run(snakemake.output.events, events, attrs, sources=snakemake.input.record)
logging.info(
    f"{rec.path} ({rec.label}): {attrs['n_impacts']} impacts; x_impact {attrs['x_impact']:.6g} m "
    f"({attrs['x_impact_source']}); noise {attrs['noise_sigma']:.3g} m; timing sigma median "
    f"{attrs['timing_sigma_median']:.3g} s, max {attrs['timing_sigma_max']:.3g} s; dt {attrs['sample_interval']:.3g} s"
)
