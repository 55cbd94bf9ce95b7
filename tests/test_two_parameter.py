"""Bifurcation curves in (w, xI) (impactosc.dynamics.two_parameter): at the paper's xI each
curve passes through the point the one-parameter code locates; elsewhere each agrees with a
bisection of the same transition by time simulation alone (no shooting, no monodromy matrix):
  - period doubling: does a small alternating deviation from the period-N orbit grow or decay?
    (the orbit itself found by time simulation too: the midpoint of two successive points cancels
    the alternating component);
  - grazing: followed down in w in steps smaller than the near-miss gap, does the attractor still
    miss the obstacle?
  - fold: started on the stable orbit above it, does the simulation settle or drift away?
"""

import dataclasses
import math

import numpy as np
import pytest

from impactosc.core.layout import S_V, S_X
from impactosc.core.simulation import simulate
from impactosc.dynamics import shoot
from impactosc.dynamics.arclength import continue_branch, folds, locate_fold
from impactosc.dynamics.bifurcation_points import locate
from impactosc.dynamics.grazing import locate_orbit_grazing
from impactosc.dynamics.two_parameter import CurveProblem, point_at, start_point, trace_curve
from impactosc.model.parameters import ModelParams

RTOL, ATOL = 1e-12, 1e-14
XI = ModelParams().xI  # the paper's obstacle, -2.086 mm
SCALE = np.array([1e-3, 1e-1])


# ------------------------------------------------------------ the one-parameter located points


def _doubling(guess, w_lo, w_hi, n):
    a = shoot(guess, w_lo, n)
    return locate("period_doubling", a, shoot([a.x0, a.v0], w_hi, n), tol=1e-9)


def _grazing():
    a = shoot([-0.00415, 0.0], 23.3)
    w, orbit, _ = locate_orbit_grazing(a, shoot([a.x0, a.v0], 23.2))
    return w, orbit


def _fold():
    branch = continue_branch(shoot([-0.004902, -0.00789], 20.0), 0.05, 20, direction=-1)
    ((a, b),) = folds(branch)
    fold = locate_fold(a, b, tol=1e-8)
    return fold.orbit.omega, fold.orbit


ONE_PARAMETER = {  # kind, N, how the one-parameter code locates it at the paper's xI
    "grazing": ("grazing", 1, _grazing),
    "doubling_1_2": ("period_doubling", 1, lambda: _doubling([-0.0079, -0.128], 37.27, 37.30, 1)),
    "doubling_2_4": ("period_doubling", 2, lambda: _doubling([-0.004556, -0.09414], 39.03, 39.045, 2)),
    "fold": ("fold", 1, _fold),
}


@pytest.fixture(scope="module", params=list(ONE_PARAMETER))
def located(request):
    kind, n, how = ONE_PARAMETER[request.param]
    w, orbit = how()
    return CurveProblem(kind, "xI", n), w, orbit


# ------------------------------------------------------------ bisections by time simulation


def _strobe(y, w, n, params):
    """Poincare points after each of n forcing periods from y at phase 0."""
    r = simulate(w, 0.0, n * 2 * math.pi / w, x0=float(y[0]), v0=float(y[1]), params=params, rtol=RTOL, atol=ATOL,
                 record=("poincare",))  # fmt: skip
    return np.column_stack([r.events["poincare"]["x"], r.events["poincare"]["v"]])[-n:]


def _centre(y, w, n, params, rounds=10, periods=40):
    """The period-n orbit near y by time simulation: the midpoint of two successive P^n points
    cancels the alternating component (multiplier near -1), the others decay in `periods`."""
    y = np.asarray(y, float)
    for _ in range(rounds):
        pts = _strobe(y, w, periods * n, params)[n - 1 :: n]
        new = 0.5 * (pts[-1] + pts[-2])
        if np.max(np.abs(new - y) / SCALE) < 1e-12:
            break
        y = new
    return new


def _alternating_growth(y, w, n, params, periods=1000, delta=1e-6):
    """Growth per P^n iterate (log) of a deviation delta (m, in x) from y, alternating in sign:
    the slope of log|x_{k+1} - x_k| once the other component has decayed (20 iterates). A delta
    of 1 um keeps the core's 1e-12 m noise and the cubic term of the map both below 1e-8."""
    pts = _strobe(np.asarray(y, float) + np.array([delta, 0.0]), w, periods * n, params)[n - 1 :: n]
    a = np.log(np.abs(np.diff(pts[:, 0])))[20:]
    return float(np.polyfit(np.arange(a.size), a, 1)[0])


def doubling_by_simulation(w_lo, w_hi, n, params, y0, tol=2e-8):
    """w of the period doubling of the period-n orbit between w_lo (it attracts) and w_hi."""
    y = _centre(y0, w_lo, n, params)
    assert _alternating_growth(y, w_lo, n, params) < 0
    assert _alternating_growth(_centre(y, w_hi, n, params), w_hi, n, params) > 0
    while w_hi - w_lo > tol:
        mid = 0.5 * (w_lo + w_hi)
        ym = _centre(y, mid, n, params)
        if _alternating_growth(ym, mid, n, params) < 0:
            w_lo, y = mid, ym
        else:
            w_hi = mid
    return 0.5 * (w_lo + w_hi)


def _last_period(y, w, params, periods=30):
    """(state after `periods`, impacts and smallest near-miss gap in the last period)."""
    t = 2 * math.pi / w
    r = simulate(w, (periods - 1) * t, t, x0=float(y[0]), v0=float(y[1]), params=params, rtol=RTOL, atol=ATOL,
                 record=("impacts", "near_misses"))  # fmt: skip
    gaps = r.events["near_misses"]["gap"]
    return r.final_state[[S_X, S_V]].copy(), r.events["impacts"]["t"].size, (gaps.min() if gaps.size else math.inf)


def _misses_at(y, w_from, gap, slope, w, params, floor=1e-13):
    """Follow the one-impact period-1 attractor from w_from (state y, near-miss gap) down to w in
    steps of at most 0.3 gap / slope, so that no step's transient reaches the obstacle. (True,
    state, gap, slope) if it still misses the obstacle at w; False once it hits, or once the gap
    is below `floor` with w still further (within floor / slope of the grazing: w is past it)."""
    while gap >= floor:
        w_next = max(w, w_from - 0.3 * gap / slope)
        y_next, impacts, g = _last_period(y, w_next, params)
        if impacts != 1 or not 0 < g < math.inf:
            break
        slope = (gap - g) / (w_from - w_next) if g != gap else slope
        y, w_from, gap = y_next, w_next, g
        if w_next == w:
            return True, y, gap, slope
    return False, y, gap, slope


def grazing_by_simulation(w_lo, w_hi, params, tol=2e-8):
    """w where the period-1 attractor's near miss becomes an impact, between w_lo and w_hi: the
    attractor followed down from rest at 30 rad/s (0.25 rad/s steps while the gap is wide, then
    steps smaller than the gap), then bisection."""
    y, path = _strobe((0.0, 0.0), 30.0, 400, params)[-1], []
    for w in np.arange(29.75, w_hi + 0.25, -0.25):
        y, impacts, gap = _last_period(y, w, params, 60)
        assert impacts == 1
        path.append((w, gap))
    (w_a, g_a), (w_b, g_b) = path[-2:]
    # the slope of the gap from the last two points, or (where the near miss has just appeared)
    # one that the bracket bounds: the gap reaches 0 above w_lo
    slope = (g_a - g_b) / (w_a - w_b) if math.isfinite(g_a) else g_b / (w_b - w_lo)
    ok, y, gap, slope = _misses_at(y, w_b, g_b, slope, w_hi, params)
    assert ok
    assert not _misses_at(y, w_hi, gap, slope, w_lo, params)[0]
    while w_hi - w_lo > tol:
        mid = 0.5 * (w_lo + w_hi)
        ok, ym, gm, sm = _misses_at(y, w_hi, gap, slope, mid, params)
        if ok:
            w_hi, y, gap, slope = mid, ym, gm, sm
        else:
            w_lo = mid
    return 0.5 * (w_lo + w_hi)


def _settles(y, w, params, periods=3000):
    """(True, end state) if the simulation from y settles at w: its Poincare point moves by less
    per period at the end than a tenth of the run earlier (on the far side of a fold it drifts
    away through the fold's ghost, faster and faster)."""
    pts = _strobe(y, w, periods, params)
    step = np.abs(np.diff(pts[:, 0]))[-periods // 10 :]
    return bool(step[-1] < 1e-12 or (step[-1] <= step[0] and step[-1] < 1e-7)), pts[-1]


BRANCH_JUMP = 3e-4  # m: below a fold the run may settle on another attractor, 1.1-1.2 mm away at
# xI = -2.1 and -1.8 mm (also two impacts per period); the branch itself moves by < 0.1 mm over
# the bisection's bracket of 0.02 rad/s


def _stays_on_branch(y, w, params):
    """(True, end state) if the run from y settles at w on the branch y lies on."""
    ok, end = _settles(y, w, params)
    return ok and abs(end[0] - y[0]) < BRANCH_JUMP, end


def fold_by_simulation(w_lo, w_hi, params, y_hi, tol=1e-7):
    """w of the fold between w_lo and w_hi: the lowest w where the run from the branch's state
    (y_hi, on the branch above the fold) settles on the branch."""
    ok, y = _stays_on_branch(y_hi, w_hi, params)
    assert ok and not _stays_on_branch(y, w_lo, params)[0]
    while w_hi - w_lo > tol:
        mid = 0.5 * (w_lo + w_hi)
        ok, ym = _stays_on_branch(y, mid, params)
        if ok:
            w_hi, y = mid, ym
        else:
            w_lo = mid
    return 0.5 * (w_lo + w_hi)


# ------------------------------------------------------------ the tests


def test_each_curve_passes_through_the_located_point(located):
    """Started 2e-3 rad/s off, the curve's point at the paper's xI is the one-parameter table's
    point; two steps out along the curve and back (p held at the paper's xI), again."""
    problem, w_located, orbit = located
    start = start_point(problem, w_located + 2e-3, orbit.x0, orbit.v0)
    assert start.value == XI and abs(start.orbit.omega - w_located) < 1e-7
    curve = trace_curve(problem, start, ds=0.1, ds_min=1e-3, value_range=(-3e-3, -1e-3), w_range=(15, 50),
                        max_points=2)  # fmt: skip
    assert len(curve.points) == 5 and curve.points[2] is start
    back = point_at(problem, curve.points[0], XI)
    assert abs(back.orbit.omega - w_located) < 1e-7
    mu = back.orbit.multipliers
    if problem.kind == "period_doubling":
        assert np.min(np.abs(mu + 1)) < 1e-6
    elif problem.kind == "fold":
        assert np.min(np.abs(mu - 1)) < 1e-6
    else:  # touches the obstacle: the grazing excursion's gap is below a picometre
        assert abs(back.events["graze_gap"]) < 1e-12
    # every point is an orbit of the model at its own xI, with its condition met
    assert all(p.orbit.residual < 1e-9 and abs(p.condition) < 1e-7 for p in curve.points)
    assert np.all(np.diff([p.value for p in curve.points]) > 0)


def _curve_point(kind, n, guess_w, guess, xi):
    """The curve's point at obstacle xi, followed from the paper's xI."""
    problem = CurveProblem(kind, "xI", n)
    start = start_point(problem, guess_w, *guess)
    box = (min(xi, XI) - 1e-4, max(xi, XI) + 1e-4)
    curve = trace_curve(problem, start, ds=0.1, ds_min=1e-4, value_range=box, w_range=(15, 50), max_points=60)
    return point_at(problem, min(curve.points, key=lambda p: abs(p.value - xi)), xi)


GRAZING_GUESS = (23.0441223, (-0.003884048, -0.020664995))
DOUBLING_GUESS = (37.2843239, (-0.007929, -0.128042))


@pytest.mark.slow  # 13-15 s: the two-parameter curves are an opt-in target
def test_grazing_and_doubling_at_another_obstacle_agree_with_time_simulation():
    """At xI = -2.5 mm. Measured: the grazing 1e-8 rad/s apart, the doubling 4e-8 (the
    bisections' resolution is 2e-8)."""
    xi = -2.5e-3
    params = dataclasses.replace(ModelParams(), xI=xi)
    graze = _curve_point("grazing", 1, *GRAZING_GUESS, xi)
    assert 24.5 < graze.orbit.omega < 24.7  # the obstacle farther out: the grazing moves up
    w = grazing_by_simulation(graze.orbit.omega - 0.01, graze.orbit.omega + 0.01, params)
    assert abs(w - graze.orbit.omega) < 1e-6
    pd = _curve_point("period_doubling", 1, *DOUBLING_GUESS, xi)
    y0 = _strobe((0.0, 0.0), pd.orbit.omega - 0.3, 400, params)[-1]  # the period-1 attractor from rest
    w = doubling_by_simulation(pd.orbit.omega - 0.01, pd.orbit.omega + 0.01, 1, params, y0)
    assert abs(w - pd.orbit.omega) < 1e-6


@pytest.mark.slow  # 13-15 s: the two-parameter curves are an opt-in target
def test_the_fold_curve_has_a_cusp_where_the_two_folds_of_the_branch_merge():
    """At xI = -1.50 mm the two-impact branch, followed in w by the one-parameter code, turns at
    two folds; the fold curve from one of them turns at a cusp in (w, xI) and comes back to
    -1.50 mm at the other one; at -1.46 mm (past the cusp) the branch has no fold. Measured: the
    cusp at w = 17.8869734, xI = -1.4801981 mm from here and from the paper's xI alike."""
    near_cusp = dataclasses.replace(ModelParams(), xI=-1.5e-3)
    start = shoot([-0.0043486, -0.0043902], 18.3, 1, near_cusp)
    ((a, b), (c, d)) = folds(continue_branch(start, 0.02, 60, near_cusp, direction=-1, w_range=(17.7, 18.4)))
    first, second = (locate_fold(*pair, near_cusp, tol=1e-8).orbit for pair in ((a, b), (c, d)))
    problem = CurveProblem("fold", "xI", 1, near_cusp)
    curve = trace_curve(problem, start_point(problem, second.omega, second.x0, second.v0), ds=0.1, ds_min=1e-4,
                        value_range=(-1.52e-3, -1.44e-3), w_range=(15, 50), max_points=20)  # fmt: skip
    (cusp,) = curve.codim_two
    assert cusp["what"] == "cusp" and cusp["located"]
    assert abs(cusp["omega"] - 17.8869734) < 1e-6 and abs(cusp["value"] + 1.4801981e-3) < 1e-9
    assert max(p.value for p in curve.points) < -1.48e-3  # the curve does not pass the cusp in xI
    beyond = next(p for p in curve.points[curve.points.index(min(curve.points, key=lambda p: p.orbit.omega)) :]
                  if p.value < -1.5e-3)  # fmt: skip
    assert abs(point_at(problem, beyond, -1.5e-3).orbit.omega - first.omega) < 1e-7
    past = dataclasses.replace(ModelParams(), xI=-1.46e-3)
    branch = continue_branch(shoot([start.x0, start.v0], 18.3, 1, past), 0.02, 60, past, direction=-1,
                             w_range=(17.7, 18.4))  # fmt: skip
    assert not folds(branch) and branch[-1].orbit.omega < 17.85  # down past the cusp's w without a turn


def test_bad_problems_are_refused():
    with pytest.raises(ValueError, match="kind must be one of"):
        CurveProblem("neimark_sacker", "xI", 1)
    with pytest.raises(ValueError, match="parameter must be one of"):
        CurveProblem("fold", "k", 1)
    problem, w, orbit = CurveProblem("period_doubling", "xI", 1), *DOUBLING_GUESS
    start = start_point(problem, w, *orbit)
    with pytest.raises(ValueError, match="outside the box"):
        trace_curve(problem, start, ds=0.1, ds_min=1e-4, value_range=(-1.5e-3, -1e-3), w_range=(15, 50), max_points=2)
    with pytest.raises(ValueError, match="ds > ds_min"):
        trace_curve(problem, start, ds=1e-4, ds_min=1e-3, value_range=(-3e-3, -1e-3), w_range=(15, 50), max_points=2)


FOLD_GUESS = (19.5330757, (-0.0047075, -0.00015576))
PD2_GUESS = (39.0362941, (-0.004556437, -0.094142028))


OBSTACLES = (-2.9e-3, -2.7e-3, -2.4e-3, -2.1e-3, -1.8e-3)  # five besides the paper's, where all four curves exist
CURVES = ("grazing", "doubling_1_2", "doubling_2_4", "fold")


@pytest.mark.slow
@pytest.mark.parametrize("curve, xi", [(c, x) for x in OBSTACLES for c in CURVES])
def test_curves_agree_with_time_simulation_at_more_obstacles(curve, xi):
    """Every curve at five obstacle positions besides the paper's, each point against a bisection
    of the same transition by time simulation alone (resolution 2e-8 rad/s, 1e-7 for the fold,
    whose bisection lags by the slow passage past a fold)."""
    params = dataclasses.replace(ModelParams(), xI=xi)
    if curve == "grazing":
        p = _curve_point("grazing", 1, *GRAZING_GUESS, xi)
        w = grazing_by_simulation(p.orbit.omega - 0.01, p.orbit.omega + 0.01, params)
    elif curve == "fold":  # started on the curve's orbit only to pick the attractor above the fold
        p = _curve_point("fold", 1, *FOLD_GUESS, xi)
        y = _strobe([p.orbit.x0, p.orbit.v0], p.orbit.omega + 0.05, 400, params)[-1]
        w = fold_by_simulation(p.orbit.omega - 0.01, p.orbit.omega + 0.01, params, y)
    else:
        n = 1 if curve == "doubling_1_2" else 2
        p = _curve_point("period_doubling", n, *(DOUBLING_GUESS if n == 1 else PD2_GUESS), xi)
        y0 = _strobe((0.0, 0.0), p.orbit.omega - 0.3, 800, params)[-1]  # the period-n attractor from rest
        w = doubling_by_simulation(p.orbit.omega - 0.01, p.orbit.omega + 0.01, n, params, y0)
    assert abs(w - p.orbit.omega) < 1e-6


def _map_rows(values):
    """Rows of the 2-D map at these obstacle positions, with the workflow's default settings."""
    from impactosc.dynamics.diagram import classify_sweep
    from impactosc.dynamics.sweep import SweepSettings, parameter_rows, regular_grid

    settings = SweepSettings(n_transient=100, n_record=50, n_initial=1000)
    tables = [classify_sweep(res, x_tol=1e-6, v_tol=1e-4, isi_tol=1e-4)
              for _, res in parameter_rows(regular_grid(20.0, 45.0, 0.25), settings, "xI", values)]  # fmt: skip
    return tables[0].omega, np.vstack([t.period for t in tables]), np.vstack([t.impacts for t in tables])


@pytest.mark.slow
def test_the_curves_separate_the_map_cells_of_different_period():
    """Five map rows (the default map's settings) against the four default curves, each followed
    from the paper's xI over -3..-1 mm: every check of the grazing and the doublings passes to one
    grid cell. A fold check may fail only where the two-impact orbit born at the fold is stable
    beyond the crossing and the map's row stays on another attractor (coexistence)."""
    from impactosc.dynamics.two_parameter import curve_record
    from impactosc.dynamics.two_parameter_map import curve_crossings, separation

    values = np.array([-3.0e-3, -2.5e-3, XI, -1.5e-3, -1.0e-3])
    omega, period, impacts = _map_rows(values)
    guesses = {"grazing": ("grazing", 1, GRAZING_GUESS), "doubling_1_2": ("period_doubling", 1, DOUBLING_GUESS),
               "doubling_2_4": ("period_doubling", 2, PD2_GUESS), "fold": ("fold", 1, FOLD_GUESS)}  # fmt: skip
    curves = {}
    for name, (kind, n, (w, guess)) in guesses.items():
        problem = CurveProblem(kind, "xI", n)
        start = start_point(problem, w, *guess)
        traced = trace_curve(problem, start, ds=0.1, ds_min=1e-4, value_range=(-3e-3, -1e-3), w_range=(17, 45),
                             max_points=300)  # fmt: skip
        curves[name] = {**curve_record(traced), "start": {"value": start.value}}
    rows = separation(omega, values, period, impacts, curves)
    assert len(rows) >= 20
    assert all(r["ok"] for r in rows if "fold" not in r["curve"]), [r for r in rows if not r["ok"]]
    for r in (r for r in rows if not r["ok"]):
        params = dataclasses.replace(ModelParams(), xI=r["value"])
        p = min(curves["fold"]["points"], key=lambda q: abs(q["value"] - r["value"]))
        (w_fold,) = curve_crossings(curves["fold"]["points"], r["value"])
        above = shoot([p["x0"], p["v0"]], w_fold + 0.3, 1, params)
        assert above.stable  # the orbit the map did not land on is there, and attracts
        j = np.argmin(np.abs(omega - above.omega))
        assert period[list(values).index(r["value"]), j] != 1
