"""Files the package writes and reads: run files, tables, JSON, provenance, atomic writes."""

from impactosc._lazy import export

export(
    globals(),
    {
        "read_run": "impactosc.io.files",
        "write_run": "impactosc.io.files",
        "read_json": "impactosc.io.files",
        "write_json": "impactosc.io.files",
        "read_table": "impactosc.io.files",
        "write_table": "impactosc.io.files",
        "atomic_write": "impactosc.io.files",
        "provenance": "impactosc.io.files",
    },
)
