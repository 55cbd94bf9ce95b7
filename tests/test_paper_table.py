"""The paper-vs-replication table names the study's own folder in its paths."""

from impactosc.io.files import read_csv
from impactosc_study.paper.table import COLUMNS, merge_tables, write_rows


def test_rows_name_the_study_folder(tmp_path):
    rows = tmp_path / "rows.csv"
    row = dict.fromkeys(COLUMNS, "1")
    row["command"] = "snakemake -j2 periodic_rows  (results/<study>/stats/periodic/periodic.json)"
    write_rows(rows, [row])
    out = [tmp_path / f"table.{ext}" for ext in ("csv", "md", "html")]
    merge_tables([rows], *out, study="myrig")
    (merged,) = read_csv(out[0])
    assert merged["command"] == "snakemake -j2 periodic_rows  (results/myrig/stats/periodic/periodic.json)"
    assert "<study>" not in out[1].read_text()
