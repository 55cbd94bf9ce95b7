"""The core against the closed-form response of the forced linear oscillator (T = 0, no contact)."""

import math

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate


def closed_form(p, omega, t, x0, v0):
    """x(t), v(t) of m x'' + c x' + k x = m0e w^2 sin(w t) from (x0, v0) at t = 0."""
    F = p.m0e * omega**2
    wn = math.sqrt(p.k / p.m)
    zeta = p.c / (2 * math.sqrt(p.k * p.m))
    wd = wn * math.sqrt(1 - zeta**2)
    # particular solution X sin(wt - psi)
    den = (p.k - p.m * omega**2) ** 2 + (p.c * omega) ** 2
    a_s = F * (p.k - p.m * omega**2) / den  # coefficient of sin
    a_c = -F * p.c * omega / den  # coefficient of cos
    xp0, vp0 = a_c, a_s * omega
    A = x0 - xp0
    B = (v0 - vp0 + zeta * wn * A) / wd
    e = np.exp(-zeta * wn * t)
    xh = e * (A * np.cos(wd * t) + B * np.sin(wd * t))
    vh = e * ((-zeta * wn * A + wd * B) * np.cos(wd * t) + (-zeta * wn * B - wd * A) * np.sin(wd * t))
    x = xh + a_s * np.sin(omega * t) + a_c * np.cos(omega * t)
    v = vh + a_s * omega * np.cos(omega * t) - a_c * omega * np.sin(omega * t)
    return x, v


@pytest.mark.parametrize("omega", [8.0, 12.74, 23.03, 40.86])
def test_poincare_points_and_window_match_closed_form(linear_params, omega):
    p = linear_params
    x0, v0 = 1e-3, -0.02
    res = simulate(
        omega,
        0.0,
        20.0,
        x0=x0,
        v0=v0,
        params=p,
        rtol=1e-12,
        atol=1e-15,
        window=Window(0.0, 20.0, 0.01),
        record=("poincare", "impacts"),
    )
    assert len(res.events["impacts"]["t"]) == 0  # the obstacle is out of reach
    pc = res.events["poincare"]
    n = int(20.0 / (2 * math.pi / omega))
    assert len(pc["t"]) == n
    # Poincare times are i * 2 pi / w exactly (one multiplication, no accumulation)
    np.testing.assert_array_equal(pc["t"], np.arange(1, n + 1) * (2 * math.pi / omega))
    x, v = closed_form(p, omega, pc["t"], x0, v0)
    scale_x = np.abs(x).max()
    # global error at rtol 1e-12 over ~20 s of a lightly damped oscillator: allow 1e-9 relative
    np.testing.assert_allclose(pc["x"], x, rtol=0, atol=1e-9 * scale_x)
    np.testing.assert_allclose(pc["v"], v, rtol=0, atol=1e-9 * np.abs(v).max())
    tr = res.trajectory
    xw, _vw = closed_form(p, omega, tr["t"], x0, v0)
    # dense output (7th order) on top of the step error: same bound
    np.testing.assert_allclose(tr["x"], xw, rtol=0, atol=1e-9 * scale_x)


def test_error_falls_with_tolerance(linear_params):
    p, omega = linear_params, 23.03
    errs = []
    for rtol in (1e-6, 1e-9, 1e-12):
        res = simulate(omega, 0.0, 10.0, x0=1e-3, params=p, rtol=rtol, atol=rtol * 1e-3, record=("poincare",))
        x, _ = closed_form(p, omega, res.events["poincare"]["t"], 1e-3, 0.0)
        errs.append(np.abs(res.events["poincare"]["x"] - x).max())
    assert errs[0] > errs[1] > errs[2]
    assert errs[2] < 1e-12
