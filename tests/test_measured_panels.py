"""Where the panels of measured data come from (Fig 2's left panel, Figs 8b, 9b, 10 lower), as the
workflow reads its config: true draws the measured group's own file, from a configured record or
else from the surrogate, which is always labelled as the surrogate; an object names a file made
elsewhere; false draws no panel (and builds nothing for it)."""

import importlib.util
from pathlib import Path

import pytest

from impactosc.records.surrogate import LABEL

REPO = Path(__file__).resolve().parents[1]


def _helper():
    spec = importlib.util.spec_from_file_location(
        "workflow_script_start", REPO / "workflow" / "scripts" / "_logging.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


helper = _helper()


def panels(tmp_path, text=None):
    """(SECOND_TRAIN, FIG02_EXPERIMENTAL, rule names) of the paper's workflow with ``text`` as an extra config."""
    files = []
    if text:
        files.append(tmp_path / "extra.yaml")
        files[0].write_text(text)
    with helper.open_workflow(files) as wf:
        return wf.globals["SECOND_TRAIN"], wf.globals["FIG02_EXPERIMENTAL"], {r.name for r in wf.rules}


def test_the_surrogate_is_labelled_so(tmp_path):
    second, fig02, rules = panels(tmp_path)
    assert second == {"file": "results/paper/runs/measured/chaos_events.h5", "label": LABEL, "built_here": True}
    assert fig02 == {"file": "results/paper/runs/measured/fig02_experimental.h5", "label": LABEL, "built_here": True}
    assert "measured_rows" in rules


@pytest.mark.parametrize(
    ("text", "label"),
    [
        ("measured:\n  chaos: {record: rig/chaos.tdms}\n", "measured record chaos.tdms"),
        ("measured:\n  chaos: {record: rig/chaos.tdms, label: rig 3 at 40.86 rad/s}\n", "rig 3 at 40.86 rad/s"),
    ],
)
def test_a_record_is_named(tmp_path, text, label):
    second, _, _ = panels(tmp_path, text)
    assert second["label"] == label and second["built_here"]


def test_a_file_made_elsewhere_and_no_panel(tmp_path):
    text = (
        "chaotic:\n  second_train: {events: elsewhere.h5, label: rig 4}\nbifurcation:\n  fig02: {experimental: false}\n"
    )
    second, fig02, rules = panels(tmp_path, text)
    assert second == {"file": "elsewhere.h5", "label": "rig 4", "built_here": False}
    assert fig02 is None
    assert "measured_rows" not in rules  # the rows judge the measured group's own train only
