"""The table of located bifurcation points and the cascade chain, on hand-made segments."""

import math

from impactosc.dynamics.orbit_table import bifurcation_table, cascade_chain, chain_ratios, multipliers_text
from impactosc_study.paper.rows.bifurcation import orbit_rows


def _pd(w, n):
    return {"kind": "period_doubling", "omega": w, "n_periods": n, "located": True, "x0": 0.0, "v0": 0.0,
            "mu_re": [-1.0, -0.1], "mu_im": [0.0, 0.0], "bracket": [w - 0.01, w + 0.01], "impacts": [n, n],
            "w_before": w - 0.01, "w_after": w + 0.01, "mu_before_re": [-0.9, -0.1], "mu_before_im": [0.0, 0.0],
            "mu_after_re": [-1.1, -0.1], "mu_after_im": [0.0, 0.0]}  # fmt: skip


def _segment(points, parent=None, near=None):
    spec = {"doubling_of": {"segment": parent, "near": near}} if parent else {"seed": {}}
    return {"spec": spec, "special_points": points, "points": []}


def test_cascade_chain_follows_the_switched_segments_only():
    # period1 doubles twice (at 20.26 and 37.28); only the segment switched at 37.28 carries on,
    # so a period-2 doubling at 20.40 on another segment must not join the chain
    segments = {
        "p1": _segment([_pd(20.26, 1), _pd(37.28, 1)]),
        "p2_low": _segment([_pd(20.40, 2)], "p1", 20.26),
        "p2": _segment([_pd(39.04, 2)], "p1", 37.28),
        "p4": _segment([_pd(39.48, 4)], "p2", 39.04),
    }
    chain = cascade_chain(segments)
    assert [p["omega"] for p in chain] == [37.28, 39.04, 39.48]
    ratios = chain_ratios(chain)
    assert len(ratios) == 1 and math.isclose(ratios[0], (39.04 - 37.28) / (39.48 - 39.04))


def test_table_pairs_each_point_with_the_sweep_reading_of_its_period():
    segments = {"p4": _segment([_pd(39.4824, 4)]), "p8": _segment([_pd(39.5666, 8)])}
    transitions = [
        {"sweep": "decreasing", "kind": "period doubling", "omega": "39.48", "omega_before": "39.5",
         "omega_after": "39.46", "detail": "period 8 -> 4", "is_grazing": "False", "grazing_omega_zero": ""},
    ]  # fmt: skip
    rows = bifurcation_table(segments, transitions)
    assert [r["period"] for r in rows] == [4, 8]
    assert rows[0]["decreasing_sweep_reads"].startswith("39.4800")
    assert rows[0]["decreasing_minus_located"] == "-0.0024"
    assert rows[1]["decreasing_sweep_reads"] == ""  # the 8 -> 4 reading is not the period-8 doubling


def test_multipliers_text():
    assert multipliers_text([0.18, 0.18], [0.63, -0.63]) == "0.18 +- 0.63i (|mu| = 0.6552)"
    assert multipliers_text([-8.3, -0.07], [0.0, 0.0]) == "-8.3, -0.07"


def test_orbit_rows_agree_only_inside_the_papers_ranges():
    chain = [_pd(37.28, 1), _pd(39.04, 2)]
    grazing = {"omega": 23.0441, "impacts": [2, 1], "mu_before": "a", "mu_after": "b"}
    rows = orbit_rows(chain, [], [grazing], "cmd")
    assert [r["agrees"] for r in rows] == ["yes", "yes"]
    rows = orbit_rows([_pd(30.0, 1)], [], [dict(grazing, omega=23.06)], "cmd")
    assert [r["agrees"] for r in rows] == ["no", "no"]
