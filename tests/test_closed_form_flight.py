"""The closed-form free-flight prototype (impactosc_bench.closed_form_flight) against SciPy.

Why: its timing is only worth projecting if its events are the core's. Start states are the
core's own free-flight pieces of the chaotic scene (after contact exits, and after band exits,
which the core reaches inside its closed-form steps); SciPy DOP853 at rtol 1e-12 with the
regularised friction is the reference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from impactosc.core.band_crossing import cross
from impactosc.core.layout import CLOSED, EXPLICIT
from impactosc.core.transitions import U_CLOSED
from impactosc.model.equations import FREE
from impactosc.model.parameters import P_EPS, ModelParams
from impactosc_bench.closed_form_flight import FREE_FLIGHT
from impactosc_bench.closed_form_piece import (
    EV_BAND,
    EV_IMPACT,
    flight_piece,
    flight_state,
    friction_correction,
    friction_residual,
)
from impactosc_bench.piece_replay import core_pieces, kind
from impactosc_bench.scene import OMEGA
from impactosc_bench.scipy_reference import model_forces

PERIOD = 2 * math.pi / OMEGA
PARAMS = ModelParams()
EDGE = U_CLOSED * PARAMS.eps
FLIGHT_KINDS = (FREE_FLIGHT, kind(EXPLICIT, FREE, CLOSED, 0))  # free flight in time steps or in closed form


@pytest.fixture(scope="module")
def flights():
    """The core's free-flight pieces of the first 3 s that start outside the band, and the flights
    from the band's far edge inside them (the core crosses the band within a closed-form step,
    band_crossing.cross): (start (t, x, v), Poincare index, core end (t, x, v), ended by an impact)."""
    p = PARAMS.as_array(OMEGA)
    pieces = core_pieces(3.0)
    out = []
    for i in range(len(pieces.codes) - 1):  # the last piece is cut by the run's end
        st, end = pieces.starts[i], pieces.ends[i]
        if pieces.codes[i] in FLIGHT_KINDS and abs(st[2]) >= EDGE * (1 - 1e-9):
            start, isec, impact = (st[0], st[1], st[2]), st[9], pieces.starts[i + 1][3] == 1
            while True:
                out.append((start, isec, end, impact))
                kind, t, x, v, isec, _ = flight_piece(p, *start, isec, PERIOD, np.empty((4, 3)))
                if kind != EV_BAND or t >= end[0] - 1e-9:  # the core's piece ends here (1e-9 s: rounding)
                    break
                ok, _, _, t1, x1, v1 = cross(p, t, x, v)
                if not ok or t1 >= end[0]:
                    break
                start = (t1, x1, v1)
    return out


def _scipy(start, t_max, params=PARAMS, rtol=1e-12):
    """SciPy to the first impact or band edge: (kind, t, dense solution)."""
    ext, _, _ = model_forces(params, OMEGA)
    t0, x0, v0 = start
    s = math.copysign(1.0, v0)
    edge = U_CLOSED * params.eps

    def impact(t, y):
        return y[0] - params.xI

    def band(t, y):
        return y[1] - s * edge

    impact.terminal, impact.direction = True, 1
    band.terminal, band.direction = True, -s
    r = solve_ivp(
        lambda t, y: [y[1], ext(t, y[0], y[1]) / params.m],
        (t0, t_max),
        [x0, v0],
        method="DOP853",
        rtol=rtol,
        atol=rtol * 1e-4,
        events=[impact, band],
        dense_output=True,
    )
    kind = EV_IMPACT if len(r.t_events[0]) else (EV_BAND if len(r.t_events[1]) else 0)
    return kind, r.t[-1], r.sol


def test_events_and_states_match_scipy(flights):
    p = PARAMS.as_array(OMEGA)
    kinds = set()
    for start, isec, core_end, core_impact in flights[:16]:
        sections = np.full((4, 3), np.nan)
        kind, t1, x1, v1, isec1, _ = flight_piece(p, *start, isec, PERIOD, sections)
        ref_kind, t_ref, sol = _scipy(start, start[0] + 1.0, rtol=1e-13)
        assert kind == ref_kind
        x_ref, v_ref = sol(t1)
        assert abs(x1 - x_ref) < 2e-12 and abs(v1 - v_ref) < 5e-11
        # the band's edge: the closed form's |v| reaches it at t1, the state handed on (above: on
        # SciPy's trajectory) adds the residual's correction, so SciPy reaches the edge later by
        # that correction over |a|; only the impact is a time to compare
        if kind == EV_IMPACT:
            assert abs(t1 - t_ref) < 1e-10  # the impact-time error of the core is ~1e-9 s
        if kind == EV_IMPACT:  # the core's own impact time
            assert core_impact and abs(t1 - core_end[0]) < 1e-10
        for ts, xs, vs in sections[: int(isec1 - isec)]:  # the Poincare states passed
            x_ref, v_ref = sol(ts)
            assert abs(xs - x_ref) < 2e-12 and abs(vs - v_ref) < 5e-11
        kinds.add(kind)
    assert kinds == {EV_IMPACT, EV_BAND}


def test_friction_residual_within_its_bound_and_corrected(flights):
    """Constant friction +-T instead of T v / sqrt(v^2 + eps^2): the closed form's error at the
    piece's end stays within the Duhamel bound, and the first-order correction removes it."""
    p = PARAMS.as_array(OMEGA)
    for start, isec, _, _ in flights[:6]:
        _, t1, x1, v1, _, _ = flight_piece(p, *start, isec, PERIOD, np.empty((4, 3)))
        _, _, sol = _scipy(start, start[0] + 1.0, rtol=1e-13)
        x_ref, v_ref = sol(t1)
        bound = friction_residual(PARAMS, *start, t1)
        assert bound["max_dF"] <= PARAMS.T * PARAMS.eps**2 / (2 * EDGE**2) * (1 + 1e-6)
        assert abs(x1 - x_ref) <= bound["bound_x"] * 1.01 + 1e-14
        assert abs(v1 - v_ref) <= bound["bound_v"] * 1.01 + 1e-13
        # the piece adds the residual's first-order correction itself (closed_flight.residual_correction):
        # it matches the bench's dense quadrature of the same integral and lands on SciPy
        dx, dv = friction_correction(PARAMS, *start, t1)
        assert abs(dx) <= bound["bound_x"] * 1.01 + 1e-14 and abs(dv) <= bound["bound_v"] * 1.01 + 1e-13
        assert abs(x1 - x_ref) < 2e-14 and abs(v1 - v_ref) < 5e-13


@pytest.mark.parametrize("above", [True, False])
def test_velocity_dip_next_to_the_band_edge_is_never_stepped_over(flights, above):
    """A dip of |v| to a minimum V far outside the band, started from just before it, with the band
    edge moved next to V: 1e-7 V below, the piece runs past the dip; 1e-7 V above (two crossings
    ~5e-5 s apart), it stops at the first."""
    base = PARAMS.as_array(OMEGA)
    for start, isec, _, _ in flights:
        t0, x0, v0 = start
        _, t_end, *_ = flight_piece(base, *start, isec, PERIOD, np.empty((4, 3)))
        ts = np.linspace(t0, t_end, 2001)
        sv = np.array([math.copysign(1.0, v0) * flight_state(base, t0, x0, v0, t)[1] for t in ts])
        inner = np.flatnonzero((sv[1:-1] < sv[:-2]) & (sv[1:-1] < sv[2:]) & (sv[1:-1] > 10 * EDGE)) + 1
        if len(inner):
            break
    else:
        pytest.fail("no piece with an interior minimum of |v|")
    i = inner[0]
    fine = np.linspace(ts[i - 1], ts[i + 1], 20001)
    speeds = np.array([abs(flight_state(base, t0, x0, v0, t)[1]) for t in fine])
    vmin, tmin = speeds.min(), fine[np.argmin(speeds)]
    ta = ts[i - 1]  # the new start, on the same trajectory just before the dip
    xa, va = flight_state(base, t0, x0, v0, ta)
    p = base.copy()
    p[P_EPS] = vmin * (1 - 1e-7 if above else 1 + 1e-7) / U_CLOSED  # the edge next to the dip
    kind, t1, _, _, _, _ = flight_piece(p, ta, xa, va, math.floor(ta / PERIOD) + 1, PERIOD, np.empty((4, 3)))
    if above:
        assert t1 > tmin + 1e-4
    else:
        # on the edge: the closed form there, before the residual's correction (large with this eps)
        _, v_edge = flight_state(p, ta, xa, va, t1)
        assert kind == EV_BAND and tmin - 1e-4 < t1 < tmin and abs(abs(v_edge) - U_CLOSED * p[P_EPS]) < 1e-11
