"""Rows of the paper-vs-replication table: one CSV of rows per figure group, merged once.

Each row: section, quantity, paper (the paper's value as printed), replication (ours),
tolerance (what counts as agreement, with its reason), agrees (yes/no/n.a.), command (how
to regenerate it). Figure groups write their own rows file (built in
:mod:`impactosc_study.paper.rows`); :func:`merge_tables` builds
results/<study>/tables/paper_vs_replication.csv, a Markdown copy, and an HTML copy for the
Snakemake report (which shows HTML files, not CSV).
"""

from __future__ import annotations

import html

from impactosc.io.files import read_csv, write_csv, write_text

COLUMNS = ("section", "quantity", "paper", "replication", "tolerance", "agrees", "command")


def agreement(ok: bool) -> str:
    """The agrees column of a row with a yes/no verdict (rows beyond the paper write n.a.)."""
    return "yes" if ok else "no"


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


def to_markdown(rows: list[dict], columns=COLUMNS) -> str:
    """Rows as a Markdown table (the paper table's columns, or `columns` of any table)."""

    def esc(s):
        return str(s).replace("|", "\\|")

    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(esc(r[c]) for c in columns) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def to_html(rows: list[dict], model: str | None = None) -> str:
    """A standalone HTML page of the table (every cell escaped); rows that do not agree are
    marked, so that they stand out in the report; `model` names the model the replication ran."""
    head = "".join(f"<th>{html.escape(c)}</th>" for c in COLUMNS)
    body = []
    for r in rows:
        cls = ' class="disagree"' if r["agrees"] == "no" else ""
        body.append(f"<tr{cls}>" + "".join(f"<td>{html.escape(str(r[c]))}</td>" for c in COLUMNS) + "</tr>")
    agree = sum(r["agrees"] == "yes" for r in rows)
    model_line = f"<p>Model: {html.escape(model)}.</p>\n" if model else ""
    return (
        '<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>Paper vs replication</title>\n'
        "<style>body{font-family:sans-serif;font-size:13px} table{border-collapse:collapse}"
        " td,th{border:1px solid #bbb;padding:3px 6px;vertical-align:top;text-align:left}"
        " th{background:#eee} tr.disagree td{background:#fdd}</style></head><body>\n"
        f"<h1>Paper vs replication</h1>\n<p>{len(rows)} rows; {agree} agree within their stated tolerance "
        f"(the tolerance column gives the reason for each).</p>\n{model_line}"
        f"<table>\n<thead><tr>{head}</tr></thead>\n<tbody>\n" + "\n".join(body) + "\n</tbody></table>\n</body></html>\n"
    )


def merge_tables(
    inputs, csv_out, md_out, html_out=None, *, model: str | None = None, study: str | None = None
) -> list[dict]:
    """Concatenate the groups' rows files into the table's CSV, Markdown (and HTML) files; the
    last two say which `model` the replication ran (config["model_source"]["description"]).
    With `study`, the rows' paths name its folder (results/paper/...) instead of results/<study>/."""
    rows = [row for path in inputs for row in read_rows(path)]
    if study is not None:
        here = f"results/{study}/"
        rows = [
            {k: v.replace("results/<study>/", here) if isinstance(v, str) else v for k, v in row.items()}
            for row in rows
        ]
    write_rows(csv_out, rows, sources=inputs)
    model_line = f"Model: {model}.\n\n" if model else ""
    write_text(md_out, f"# Paper vs replication\n\n{model_line}" + to_markdown(rows))
    if html_out is not None:
        write_text(html_out, to_html(rows, model))
    return rows
