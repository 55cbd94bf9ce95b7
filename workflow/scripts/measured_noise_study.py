"""Noise study: the rates' and the realism rows merged into the study's table and JSON.

Reads input.rate_json, input.rate_csv (each sampling rate's rows, in the order of the config's rates),
input.realism_json and input.realism_csv; writes output.csv and output.json (with ISI kernel densities).

The table's cells are copied as the parts wrote them, so each number is formatted once.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_study")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_csv, read_json, write_csv, write_json
from impactosc_study.noise_study import TABLE_COLUMNS

i = snakemake.input
json_rows = [row for path in [*i.rate_json, *i.realism_json] for row in read_json(path)["rows"]]
csv_rows = [row for path in [*i.rate_csv, *i.realism_csv] for row in read_csv(path)]
if len(json_rows) != len(csv_rows):
    raise ValueError(f"the parts' JSON files hold {len(json_rows)} rows, their CSV files {len(csv_rows)}")
sources = [*i.rate_json, *i.realism_json]
write_json(snakemake.output.json, {"rows": json_rows}, sources=sources)
write_csv(snakemake.output.csv, csv_rows, TABLE_COLUMNS, sources=sources)
logging.info(f"{len(json_rows)} rows from {len(i.rate_json)} rate(s) and {len(i.realism_json)} realism part(s)")
