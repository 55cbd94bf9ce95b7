"""Rows of the paper-vs-replication table: one CSV of rows per figure group, merged once.

Each row: section, quantity, paper (the paper's value as printed), replication (ours),
tolerance (what counts as agreement, with its reason), agrees (yes/no/n.a.), command (how
to regenerate it). Figure groups write their own rows file (built in
:mod:`impactosc.paper.rows`); :func:`merge_tables` builds
results/tables/paper_vs_replication.csv and a Markdown copy.
"""

from __future__ import annotations

from ..files import read_csv, write_csv, write_text

COLUMNS = ("section", "quantity", "paper", "replication", "tolerance", "agrees", "command")


def write_rows(path, rows: list[dict], *, sources=None) -> None:
    """Write rows (dicts with exactly COLUMNS as keys) to a CSV file, every cell as str();
    `sources` (input files) go to its provenance sidecar."""
    for row in rows:
        missing = set(COLUMNS) - set(row)
        extra = set(row) - set(COLUMNS)
        if missing or extra:
            raise ValueError(
                f"table row {row.get('quantity', row)!r}: missing {sorted(missing)}, unknown {sorted(extra)}"
            )
    write_csv(path, [{k: str(row[k]) for k in COLUMNS} for row in rows], COLUMNS, sources=sources)


def read_rows(path) -> list[dict]:
    return read_csv(path)


def to_markdown(rows: list[dict]) -> str:
    def esc(s):
        return str(s).replace("|", "\\|")

    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(esc(r[c]) for c in COLUMNS) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def merge_tables(inputs, csv_out, md_out) -> list[dict]:
    rows = [row for path in inputs for row in read_rows(path)]
    write_rows(csv_out, rows, sources=inputs)
    write_text(md_out, "# Paper vs replication\n\n" + to_markdown(rows))
    return rows
