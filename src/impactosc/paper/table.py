"""Rows of the paper-vs-replication table: one CSV of rows per figure group, merged once.

Each row: section, quantity, paper (the paper's value as printed), replication (ours),
tolerance (what counts as agreement, with its reason), agrees (yes/no/n.a.), command (how
to regenerate it). Figure groups write their own rows file; ``merge_tables`` builds
results/tables/paper_vs_replication.csv and a Markdown copy.
"""

from __future__ import annotations

import csv
from pathlib import Path
from ..files import atomic_write

COLUMNS = ("section", "quantity", "paper", "replication", "tolerance", "agrees", "command")


def _atomic_write_text(path: Path, text: str) -> None:
    with atomic_write(path) as tmp, open(tmp, "w", newline="") as f:
        f.write(text)


def write_rows(path, rows: list[dict]) -> None:
    """Write rows (dicts with exactly COLUMNS as keys) to a CSV file."""
    import io

    for row in rows:
        missing = set(COLUMNS) - set(row)
        extra = set(row) - set(COLUMNS)
        if missing or extra:
            raise ValueError(f"table row {row.get('quantity', row)!r}: missing {sorted(missing)}, unknown {sorted(extra)}")
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    w.writeheader()
    for row in rows:
        w.writerow({k: str(row[k]) for k in COLUMNS})
    _atomic_write_text(Path(path), buf.getvalue())


def read_rows(path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def to_markdown(rows: list[dict]) -> str:
    def esc(s):
        return str(s).replace("|", "\\|")

    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(esc(r[c]) for c in COLUMNS) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def merge_tables(inputs, csv_out, md_out) -> list[dict]:
    rows = [row for path in inputs for row in read_rows(path)]
    write_rows(csv_out, rows)
    _atomic_write_text(Path(md_out), "# Paper vs replication\n\n" + to_markdown(rows))
    return rows
