"""Noise study: the levels' and the realism rows merged into the study's table and JSON
(rule measured_noise_study).

Reads snakemake.input.level_json and .level_csv (the rows of each noise level, in the order of
the levels), .realism_json and .realism_csv (the sensor-realism rows; empty when none are
configured) and snakemake.params.rates; writes snakemake.output.csv (one row per rate x noise x
extraction method, then one per sensor-realism case) and .json (the same rows with ISI kernel
densities, for the figure), in the order impactosc_study.noise_study.noise_study gives them.
The table's cells are copied as the parts wrote them, so each number is formatted once.
"""

from _logging import configure_logging

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
