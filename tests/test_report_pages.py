"""The Snakemake report's pages: every caption is valid reStructuredText (a stray |v| or *
renders wrong without failing the build), and the paper table's HTML copy escapes its cells
and marks the rows that disagree."""

import io
from pathlib import Path

import docutils.core
import pytest

from impactosc_study.paper.table import COLUMNS, to_html

REPORT = Path(__file__).resolve().parents[1] / "workflow" / "report"


@pytest.mark.parametrize("page", sorted(REPORT.glob("*.rst")), ids=lambda p: p.name)
def test_caption_is_clean_rst(page):
    warnings = io.StringIO()
    docutils.core.publish_string(
        page.read_text(), writer="null", settings_overrides={"warning_stream": warnings, "report_level": 2}
    )
    assert warnings.getvalue() == "", warnings.getvalue()


def test_table_html_escapes_and_marks_disagreement():
    rows = [
        dict.fromkeys(COLUMNS, "a<b") | {"agrees": "yes"},
        dict.fromkeys(COLUMNS, "x & y") | {"agrees": "no"},
    ]
    page = to_html(rows)
    assert "a<b" not in page and "a&lt;b" in page and "x &amp; y" in page
    assert page.count('<tr class="disagree">') == 1
    assert "2 rows; 1 agree" in page
