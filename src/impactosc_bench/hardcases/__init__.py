"""Hard cases for the core: each says what it checks, what it measured and the bound.

Every case function returns rows ``{case, check, measured, bound, unit, passed, detail}``;
the tests (tests/test_hard_*.py) call them at reduced size and assert ``passed``; the
workflow (rule hard_cases) calls them at full size and writes
results/<study>/tables/work_precision/hard_cases.csv.
The references are independent of the core: SciPy's solvers, a fixed-step scan of SciPy's
dense output with an acceleration bound between samples, a piecewise closed-form Coulomb
(eps -> 0) solution, or an exact scaling law of the contact model.

Cases
-----
grazing      w swept through the grazing bifurcation; near misses and contacts of 1e-9 m
chattering   shrinking impact sequences (chaos at t < 1.1 s; a bouncing-to-rest set)
sticking     dry friction up to the forcing amplitude against the Coulomb limit; sticking
             on the obstacle (Hunt-Crossley |v|^n3 at v = 0) stays fast
regularisation  eps down to 1e-9 m/s and kI x 100: statistics and contact scaling
coincidence  an impact exactly at a Poincare time; events exactly at the end of a run
long_run     10^4 s of chaos: memory bounded by the stored events, no drift of the rate

Modules: :mod:`.grazing` (grazing), :mod:`.impacts` (chattering, coincidence),
:mod:`.sticking` (sticking, with the Coulomb closed form), :mod:`.chaos` (regularisation,
long run); :mod:`.checks` holds the table row. This package runs them all (:func:`run_all`,
the entry of rule hard_cases), the impact checks alone (:func:`impact_checks`, which the paper's
table cites) and re-exports every case.
"""

from __future__ import annotations

import dataclasses

from impactosc.core.simulation import warm_up
from impactosc.model.parameters import ModelParams
from impactosc_bench.hardcases.chaos import long_run_case, regularisation_case
from impactosc_bench.hardcases.checks import row
from impactosc_bench.hardcases.grazing_sweep import grazing_case, scan_free_flight
from impactosc_bench.hardcases.impacts import (  # noqa: F401 (tests)
    _shrinking_runs,
    bounce_to_rest_case,
    chattering_case,
    coincidence_case,
)
from impactosc_bench.hardcases.sticking import CoulombOscillator, stick_on_obstacle_case, stick_slip_case

__all__ = [
    "impact_checks",
    "run_all",
    "row",
    "grazing_case",
    "scan_free_flight",
    "chattering_case",
    "bounce_to_rest_case",
    "CoulombOscillator",
    "stick_slip_case",
    "stick_on_obstacle_case",
    "regularisation_case",
    "coincidence_case",
    "long_run_case",
]


def impact_checks(hc: dict, log=print) -> list[dict]:
    """The checks that no impact is missed or invented, which time nothing: the grazing sweep
    against an independent fixed-step scan and the shrinking impact sequences against SciPy (at
    the sizes of the ``hard_cases`` config section). The paper's table cites them (rule
    impact_checks); they are the first rows of :func:`run_all`'s table."""
    warm_up()
    base = ModelParams()
    bounce = dataclasses.replace(base, b=0.1)
    g = hc["grazing"]
    rows = grazing_case(base, fine_points=g["fine_points"], fine_halfwidth=g["fine_halfwidth"], log=log)
    rows += chattering_case(base, 40.86, 1.1, "chaotic scene, first 1.1 s", log=log)
    rows += chattering_case(bounce, 8.0, 5.1, "bouncing to rest (w = 8, b = 0.1)", min_len=10, log=log)
    return rows


def run_all(hc: dict, log=print, impact_rows=None) -> list[dict]:
    """Every case at the sizes of the ``hard_cases`` config section (model BC throughout;
    each case states the parameters it changes). ``impact_rows``: the rows of
    :func:`impact_checks` when they were run already (the workflow's impact_checks job)."""
    if impact_rows is None:
        rows = impact_checks(hc, log=log)  # warms the core up itself
    else:
        warm_up()
        rows = list(impact_rows)
    bounce = dataclasses.replace(ModelParams(), b=0.1)
    s, r, lr = hc["sticking"], hc["regularisation"], hc["long_run"]
    rows += bounce_to_rest_case(bounce, 8.0, 20.0, log=log)
    rows += stick_slip_case(ratios=tuple(s["ratios"]), eps_values=tuple(s["eps"]), periods=s["periods"], log=log)
    rows += stick_on_obstacle_case(log=log)
    rows += regularisation_case(
        eps_values=tuple(r["eps"]), kI_factor=r["kI_factor"], ensemble_x0=tuple(r["ensemble_x0"]), log=log
    )
    rows += coincidence_case(log=log)
    rows += long_run_case(duration=lr["duration"], block=lr["block"], log=log)
    return rows
