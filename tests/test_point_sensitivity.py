"""Sensitivities of a located bifurcation point by implicit differentiation, against relocating
it with the parameter moved, and the delta method's standard error."""

import dataclasses

import numpy as np
import pytest

from impactosc.dynamics.bifurcation_points import crossings, follow, locate
from impactosc.dynamics.point_sensitivity import delta_method_se, point_sensitivities
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


@pytest.mark.parametrize(("field", "step"), [("xI", 1e-7), ("k", 1e-3)])
def test_implicit_derivative_is_the_relocated_points(doubling, field, step):
    p, bracket, w, orbit = doubling
    assert w == pytest.approx(37.2843, abs=1e-4)
    s = point_sensitivities("period_doubling", w, orbit, p, fields=(field,))[field]
    # measured: dw*/dxI -1600.049 against -1600.026 relocated (1.4e-5 relative)
    assert s == pytest.approx(_relocated(p, bracket, field, step), rel=1e-4)


def test_delta_method_and_its_checks(doubling):
    s = {"k": 2.0, "xI": -1600.0}
    # a diagonal covariance: the errors add in quadrature; a name without a sensitivity adds 0
    C = np.diag([0.5**2, (2e-6) ** 2, 1.0])
    assert delta_method_se(s, ["k", "xI", "b"], C) == pytest.approx(np.hypot(2.0 * 0.5, 1600.0 * 2e-6))
    with pytest.raises(ValueError, match="covariance of shape"):
        delta_method_se(s, ["k"], C)
    p, _bracket, w, orbit = doubling
    with pytest.raises(ValueError, match="kind must be one of"):
        point_sensitivities("grazing", w, orbit, p)
    with pytest.raises(ValueError, match="unknown model parameter"):
        point_sensitivities("period_doubling", w, orbit, p, fields=("stiffness",))
