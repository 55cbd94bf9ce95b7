"""Noise study: the levels' and the realism rows merged into the study's table and JSON.

Reads input.level_json, input.level_csv (each noise level's rows, in order), input.realism_json,
input.realism_csv and params.rates; writes output.csv and output.json (with ISI kernel densities).

The table's cells are copied as the parts wrote them, so each number is formatted once.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_study")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_csv, read_json, write_csv, write_json
from impactosc_study.noise_study import TABLE_COLUMNS, merge_levels

i = snakemake.input
n_rates = len(snakemake.params.rates)
json_rows = merge_levels([read_json(path)["rows"] for path in i.level_json], n_rates)
csv_rows = merge_levels([read_csv(path) for path in i.level_csv], n_rates)
json_rows += [row for path in i.realism_json for row in read_json(path)["rows"]]
csv_rows += [row for path in i.realism_csv for row in read_csv(path)]
if len(json_rows) != len(csv_rows):
    raise ValueError(f"the parts' JSON files hold {len(json_rows)} rows, their CSV files {len(csv_rows)}")
sources = [*i.level_json, *i.realism_json]
write_json(snakemake.output.json, {"rows": json_rows}, sources=sources)
write_csv(snakemake.output.csv, csv_rows, TABLE_COLUMNS, sources=sources)
logging.info(f"{len(json_rows)} rows from {len(i.level_json)} noise level(s) and {len(i.realism_json)} realism part(s)")
