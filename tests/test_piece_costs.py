"""The piece-by-piece breakdown of the core's work (impactosc_bench.piece_costs) on a short run.

Why: its times are worth reading only if its pieces are the core's own work. On 4 s of the
chaotic scene: the step attempts of the kinds add up to the core's own counters for the same run,
the replay of each kind repeats its attempts, each contact begins at an impact the core records,
with one onset, and the contact windows share out the contact's attempts. No timing is asserted.
"""

from __future__ import annotations

import numpy as np
import pytest

from impactosc.core.layout import EXPLICIT, MODE_KEYS, MODE_NAMES, S_FIELD, S_T, SLOW_STIFF, TIME
from impactosc.core.simulation import simulate
from impactosc.model.equations import CONTACT, CUT, FREE
from impactosc_bench.benchmarks_report import benchmark_rows
from impactosc_bench.piece_costs import ONSET, breakdown, contact_windows, markdown, row_name, summarise, table_rows
from impactosc_bench.piece_replay import RTOL, core_pieces, kind, kind_of
from impactosc_bench.scene import OMEGA

T_END = 4.0  # s from rest: about 30 contacts


@pytest.fixture(scope="module")
def run():
    """The core's pieces over T_END and simulate's run of the same scene."""
    return core_pieces(T_END), simulate(OMEGA, 0.0, T_END, rtol=RTOL, atol=RTOL / 100, record=("impacts",))


def test_attempts_of_the_kinds_are_the_cores_own_counters(run):
    pc, res = run
    work = breakdown(pc)
    assert sum(r["attempts"] for r in work["rows"]) == work["attempts"] == res.attrs["n_attempts"]
    kinds = [kind_of(c) for c in pc.codes]
    for mode, key in enumerate(MODE_KEYS):  # explicit attempts per variable: the core's C_BY_MODE counters
        explicit = sum(int(a) for (slow, _, m, _), a in zip(kinds, pc.attempts) if slow == EXPLICIT and m == mode)
        assert explicit == res.attrs[f"n_attempts_{key}"] == pc.by_mode[mode]
    names = [r["piece"] for r in work["rows"]]
    assert names[0] in ("free flight, in t", "free flight, in closed form")  # whichever the core uses
    # the band's own piece runs only where closed-form flight does not cross the band in one go
    # (band_crossing.cross declines: none in these 4 s, ~1.5 % of the crossings over 500 s)
    if names[1] == "friction band, in asinh(v/eps)":
        names.pop(1)
    assert names[1:5] == [
        "contact onset, in sqrt(x - xI)",
        "turn to v = 0, in |v|^n3",
        "restitution, in |v|^n3",
        "exit, in sqrt(x - xI)",
    ]


def test_replay_of_each_row_repeats_its_attempts(run):
    pc, _ = run
    names = np.array([row_name(c) for c in pc.codes])
    for r in breakdown(pc)["rows"]:
        attempts, _ = pc.replay(names == r["piece"])
        assert attempts == r["attempts"] > 0, r["piece"]


def test_each_contact_begins_at_a_recorded_impact_with_one_onset(run):
    pc, res = run
    cw = contact_windows(pc)
    impacts = res.events["impacts"]["t"]
    n = len(cw["t_on"])
    assert n >= 20 and len(impacts) - n in (0, 1)  # a contact the run ends inside is not complete
    assert np.array_equal(cw["t_on"], impacts[:n])
    assert np.all(cw["onsets"] == 1) and np.all(cw["first_kind"] == ONSET)
    assert np.all((cw["t_on"] < cw["t_v0"]) & (cw["t_v0"] < cw["t_off"]))


def test_contact_windows_share_out_the_contacts_attempts(run):
    pc, _ = run
    cw = contact_windows(pc)
    in_contact = pc.starts[:, S_FIELD] != FREE
    t = pc.starts[:, S_T]
    from_pieces = [pc.attempts[in_contact & (t >= a) & (t < b)].sum() for a, b in zip(cw["t_on"], cw["t_off"])]
    assert np.array_equal(cw["windows"].sum(axis=1), from_pieces)
    assert np.array_equal(cw["attempts"], from_pieces)
    assert np.all(cw["windows"] > 0)  # each window of each contact takes steps


def test_a_kind_not_in_the_name_table_is_a_row_named_from_the_layout():
    assert row_name(kind(EXPLICIT, CUT, TIME, 0)) == "contact past the cut, in t"
    new_variable = len(MODE_NAMES)  # a variable the core does not have yet
    assert row_name(kind(EXPLICIT, FREE, new_variable, 0)) == f"free flight, in variable {new_variable}"
    assert row_name(kind(SLOW_STIFF, CONTACT, TIME, 0)) == "stiff creep in contact, implicit in t"
    for code in (kind(EXPLICIT, CONTACT, 3, -1), kind(SLOW_STIFF, CUT, TIME, 0)):
        assert kind(*kind_of(code)) == code


def test_tables_add_the_rows_up(run):
    pc, _ = run
    work = breakdown(pc)
    walls = [{"core": 2.0 + k, **{r["piece"]: 0.1 * (i + 1) for i, r in enumerate(work["rows"])}} for k in range(3)]
    m = summarise(work, walls, "this core")
    assert sum(r["share"] for r in m["rows"]) == pytest.approx(1.0)
    assert m["pieces_us"] == pytest.approx(sum(r["us_per_period"] for r in m["rows"]))
    assert m["core_us"] == pytest.approx(3.0e6 / work["periods"])
    text = markdown(m, "command")
    assert "| turn to v = 0, in \\|v\\|^n3 |" in text and text.count("\n| ") == len(m["rows"]) + 3 + 1 + 3 + 1
    rows = table_rows([m])
    assert [r["piece"] for r in rows][-2:] == ["sum of the pieces", "core"]
    report_row = next(r for r in benchmark_rows([], [], [], "command", rows) if "by kind of piece" in r["quantity"])
    assert f"core {m['core_us']:.1f} us" in report_row["replication"]
    assert "turn to v = 0, in |v|^n3" in report_row["replication"]
