"""Sensitivities of a located bifurcation point by implicit differentiation, against relocating
it with the parameter moved, and the delta method's standard error."""

import dataclasses

import numpy as np
import pytest

from impactosc.dynamics.bifurcation_points import crossings, follow, locate
from impactosc.dynamics.point_sensitivity import FIELDS, delta_method_se, point_sensitivities
from impactosc.dynamics.shooting import shoot
from impactosc.model.parameters import ModelParams


@pytest.fixture(scope="module")
def doubling():
    """Model BC's first period doubling of the period-1 branch (w = 37.284 rad/s) and its bracket."""
    p = ModelParams()
    orbits = follow(np.linspace(37.0, 37.5, 6), [p.xI - 1e-4, 0.0], 1, p)
    (bracket,) = crossings(orbits, "period_doubling")
    w, orbit = locate("period_doubling", *bracket, p, tol=1e-10)
    return p, bracket, w, orbit


def _relocated(p, bracket, field, step):
    """The doubling relocated with one parameter moved by +-step: the central difference of w*."""
    ws = []
    for s in (step, -step):
        q = dataclasses.replace(p, **{field: getattr(p, field) + s})
        a, b = (shoot([o.x0, o.v0], o.omega, 1, q) for o in bracket)
        ws.append(locate("period_doubling", a, b, q, tol=1e-12)[0])
    return (ws[0] - ws[1]) / (2 * step)


#: Every fitted parameter; by default k, c (the weakest, where too small a step showed) and xI,
#: the others with the slow tests.
ALL_FIELDS = [f if f in ("k", "c", "xI") else pytest.param(f, marks=pytest.mark.slow) for f in FIELDS]


@pytest.mark.parametrize("field", ALL_FIELDS)
def test_implicit_derivative_is_the_relocated_points(doubling, field):
    p, bracket, w, orbit = doubling
    assert w == pytest.approx(37.2843, abs=1e-4)
    s = point_sensitivities("period_doubling", w, orbit, p, fields=(field,))[field]
    step = 1e-7 if field == "xI" else 1e-4 * abs(getattr(p, field))
    # measured: within 1.1e-4 relative for c (the relocated difference is stable to 1e-8 over
    # steps of 1e-4 to 1e-3 of c: the gap is the implicit derivative's, 6.2e-5 with the
    # time-stepped free flight), dw*/dxI -1600.074 against -1600.043 relocated, 1.9e-5, with the
    # library's 1e-7 m step of xI; the weak ones (c, T, n3, kI) are where too small a difference
    # step shows the test function's noise (0.6-1 % at 1e-6 of the value). Bound 2e-4: the delta
    # method's standard errors need far less
    assert s == pytest.approx(_relocated(p, bracket, field, step), rel=2e-4)


def test_delta_method_and_its_checks(doubling):
    s = {"k": 2.0, "xI": -1600.0}
    # a diagonal covariance: the errors add in quadrature; a name without a sensitivity adds 0
    C = np.diag([0.5**2, (2e-6) ** 2, 1.0])
    assert delta_method_se(s, ["k", "xI", "b"], C) == pytest.approx(np.hypot(2.0 * 0.5, 1600.0 * 2e-6))
    with pytest.raises(ValueError, match="covariance of shape"):
        delta_method_se(s, ["k"], C)
    p, _bracket, w, orbit = doubling
    with pytest.raises(ValueError, match="kind must be one of"):
        point_sensitivities("cusp", w, orbit, p)
    with pytest.raises(ValueError, match="unknown model parameter"):
        point_sensitivities("period_doubling", w, orbit, p, fields=("stiffness",))


def _identification_sized_covariance(p):
    """(names, C): 0.3-2 % on k, c, T, m0e, 1 um on xI, two strong correlations (k-xI 0.6, c-T -0.9)."""
    names = ["k", "c", "T", "m0e", "xI"]
    se = np.array([0.005 * p.k, 0.01 * p.c, 0.02 * p.T, 0.003 * p.m0e, 1e-6])
    R = np.eye(5)
    R[0, 4] = R[4, 0] = 0.6
    R[1, 2] = R[2, 1] = -0.9
    return names, R * np.outer(se, se)


@pytest.mark.slow
def test_delta_method_se_is_the_spread_of_relocated_draws(doubling):
    """200 parameter sets drawn from a covariance of identification's size (0.3-2 % on the ratios,
    1 um on xI, two strong correlations), the doubling relocated for each (about 80 s)."""
    from impactosc.dynamics.point_sensitivity import relocated_draws

    p, _bracket, w, orbit = doubling
    names, C = _identification_sized_covariance(p)
    s = point_sensitivities("period_doubling", w, orbit, p, fields=tuple(names))
    ws = relocated_draws("period_doubling", w, orbit, p, names, C, 200, seed=1, sensitivities=s)
    print(f"doubling: spread {np.std(ws, ddof=1):.4f} rad/s, delta method {delta_method_se(s, names, C):.4f}")
    assert not np.isnan(ws).any()
    # the spread of 200 draws is known to 5 % (its standard error): 15 % is three of them
    assert np.std(ws, ddof=1) == pytest.approx(delta_method_se(s, names, C), rel=0.15)
    assert np.mean(ws) == pytest.approx(w, abs=3 * delta_method_se(s, names, C) / np.sqrt(200))


@pytest.fixture(scope="module")
def grazing():
    """The grazing of model BC's period-1 orbit (w = 23.0441 rad/s), from two near-miss orbits."""
    from impactosc.dynamics.grazing import locate_orbit_grazing

    p = ModelParams()
    a = shoot([-0.00415, 0.0], 23.3)
    b = shoot([a.x0, a.v0], 23.2)
    w, orbit, _gap = locate_orbit_grazing(a, b, p)
    return p, (a, b), w, orbit


@pytest.mark.parametrize("field", ALL_FIELDS)
def test_grazing_sensitivity_is_the_relocated_grazings(grazing, field):
    from impactosc.dynamics.grazing import locate_orbit_grazing

    p, pair, w, orbit = grazing
    s = point_sensitivities("grazing", w, orbit, p, fields=(field,))[field]
    step = 1e-8 if field == "xI" else 1e-6 * abs(getattr(p, field))
    ws = []
    for sign in (1, -1):
        q = dataclasses.replace(p, **{field: getattr(p, field) + sign * step})
        a, b = (shoot([o.x0, o.v0], o.omega, 1, q) for o in pair)
        ws.append(locate_orbit_grazing(a, b, q)[0])
    # measured: within 1.9e-5 relative for every parameter (c); dw*/dxI -3860.538 (extrapolated to
    # gap 0) against -3860.537 relocated, where at a gap of 1e-7 m alone it is -3860.438 (2.6e-5
    # off): the extrapolation removes what is linear in the gap
    assert s == pytest.approx((ws[0] - ws[1]) / (2 * step), rel=1e-4)


@pytest.mark.slow
def test_grazing_delta_method_se_is_the_spread_of_relocated_draws(grazing):
    """The same covariance, the grazing relocated for 200 draws (about 45 s): measured spread
    0.0574 rad/s against the delta method's 0.0580 (printed with -s)."""
    from impactosc.dynamics.point_sensitivity import relocated_draws

    p, _pair, w, orbit = grazing
    names, C = _identification_sized_covariance(p)
    s = point_sensitivities("grazing", w, orbit, p, fields=tuple(names))
    ws = relocated_draws("grazing", w, orbit, p, names, C, 200, seed=1, sensitivities=s)
    print(f"grazing: spread {np.std(ws, ddof=1):.4f} rad/s, delta method {delta_method_se(s, names, C):.4f}")
    assert not np.isnan(ws).any()
    assert np.std(ws, ddof=1) == pytest.approx(delta_method_se(s, names, C), rel=0.15)


def test_curve_point_sensitivities_are_the_points_at_the_curves_start(doubling):
    """A two-parameter curve's band: its extended system, differentiated at the curve's point at
    the model's own xI, gives the same dw*/dp as the one-parameter point (the same doubling)."""
    from impactosc.dynamics.curve_sensitivity import curve_point_sensitivities
    from impactosc.dynamics.two_parameter import CurveProblem, start_point

    p, _bracket, w, orbit = doubling
    problem = CurveProblem("period_doubling", "xI", 1, p)
    start = start_point(problem, w, orbit.x0, orbit.v0)
    point = {"omega": start.orbit.omega, "value": start.value, "x0": start.orbit.x0, "v0": start.orbit.v0}
    fields = ("k", "c", "n3")
    ours = curve_point_sensitivities(problem, point, fields)
    theirs = point_sensitivities("period_doubling", w, orbit, p, fields=fields)
    # measured against the relocated doubling: the curve's 2.9e-4 (c) and the point's 6.2e-5
    # apart at most; 1e-3 allows both, far below what a band shows
    for f in fields:
        assert ours[f] == pytest.approx(theirs[f], rel=1e-3), f
    with pytest.raises(ValueError, match="the curve's own parameter"):
        curve_point_sensitivities(problem, point, ("k", "xI"))


def test_normal_draws_follow_a_badly_scaled_covariance():
    """Variances 30 orders apart (an identified model's kI against xI), correlated at 0.99: the
    draws' sample covariance, scaled to a correlation, is the matrix's within sampling error."""
    from impactosc.dynamics.point_sensitivity import normal_draws

    sd = np.array([1e6, 1.0, 1e-9])
    R = np.array([[1.0, 0.99, -0.5], [0.99, 1.0, -0.45], [-0.5, -0.45, 1.0]])
    x = normal_draws(np.random.default_rng(0), [2e8, 5.0, -2e-3], R * np.outer(sd, sd), 100_000)
    got = np.cov(x.T) / np.outer(sd, sd)
    # a sample correlation of 1e5 draws is within 5 / sqrt(1e5) = 0.016 of the true one
    np.testing.assert_allclose(got, R, atol=0.016)
    # and the mean within 5 of its standard errors, sd / sqrt(1e5)
    assert np.all(np.abs(x.mean(axis=0) - [2e8, 5.0, -2e-3]) <= 5 * sd / np.sqrt(x.shape[0]))


def test_grazing_relocated_with_an_identified_models_small_covariance(grazing):
    """An identified model's grazing moves by micro-rad/s (se 7.7e-6 rad/s on the workflow's
    identified surrogate): its relocation starts from near-miss orbits far enough out to be shot,
    and every draw is found, where the linear prediction puts it."""
    from impactosc.dynamics.point_sensitivity import relocated_draws

    p, _pair, w, orbit = grazing
    names = ["k", "xI"]
    C = np.diag([(1e-6 * p.k) ** 2, 2e-9**2])
    s = point_sensitivities("grazing", w, orbit, p, fields=tuple(names))
    se = delta_method_se(s, names, C)
    assert 1e-6 < se < 1e-4
    ws = relocated_draws("grazing", w, orbit, p, names, C, 4, seed=2, sensitivities=s)
    assert np.isfinite(ws).all()
    # each draw where the sensitivities put it, to 1 % of its standard error (linear at this
    # scale); the draws' parameters rebuilt from the same seed
    from impactosc.dynamics.point_sensitivity import normal_draws

    drawn = normal_draws(np.random.default_rng(2), [p.k, p.xI], C, 4)
    predicted = w + (drawn - [p.k, p.xI]) @ [s["k"], s["xI"]]
    np.testing.assert_allclose(ws, predicted, rtol=0, atol=0.01 * se)


@pytest.fixture(scope="module")
def fold():
    """Model BC's fold of the period-1 orbit with two impacts (w = 19.5331 rad/s): located here
    from the state the workflow's period1 segment reports there, rounded (a start only)."""
    from impactosc.dynamics.point_sensitivity import fold_near
    from impactosc.dynamics.shooting import PeriodicOrbit, monodromy

    p = ModelParams()
    y, w = np.array([-4.7075e-3, -1.558e-4]), 19.5331
    _image, M = monodromy(y, w, 1, p)
    start = PeriodicOrbit(w, 1, *y, M, np.linalg.eigvals(M), 0.0, 0)
    return p, fold_near(start, p, 2e-3).orbit


@pytest.mark.parametrize(("field", "step"), [("xI", 1e-8), ("c", 1e-4 * 6.6511)])
def test_fold_sensitivity_is_the_relocated_folds(fold, field, step):
    from impactosc.dynamics.point_sensitivity import fold_near

    p, orbit = fold
    assert orbit.omega == pytest.approx(19.533076, abs=1e-6)
    s = point_sensitivities("fold", orbit.omega, orbit, p, fields=(field,))[field]
    ws = [fold_near(orbit, dataclasses.replace(p, **{field: getattr(p, field) + d}), 2e-3).orbit.omega
          for d in (step, -step)]  # fmt: skip
    # measured: dw*/dxI -2563.7258 and dw*/dc 0.0407407 against the relocated folds, within 3.1e-9
    assert s == pytest.approx((ws[0] - ws[1]) / (2 * step), rel=1e-5)
