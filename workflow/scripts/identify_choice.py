"""Merge the model-choice candidates into the table of which model the records support.

Reads input.parts (one row per candidate); writes output.csv and output.md (ranked by BIC, a failed fit last).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_choice")
configure_logging(snakemake)

import logging

from impactosc.identification.choice import choice_markdown, rank
from impactosc.io.files import read_json, write_table, write_text

rows = rank([read_json(path)["row"] for path in snakemake.input.parts])
write_table(snakemake.output.csv, rows, sources=list(snakemake.input.parts))
write_text(snakemake.output.md, choice_markdown(rows))
logging.info(f"supported: {rows[0]['law']}, {rows[0]['friction']}" if rows[0]["supported"] else "no fit succeeded")
