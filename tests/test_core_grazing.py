"""Grazing: contacts and near misses of 1e-9 m are neither missed nor invented.

Brute-force truth: the forced linear oscillator (T = 0) started on its periodic orbit has a
closed-form x(t), so every maximum, its height and every crossing of a level xI are known
exactly. The obstacle is put delta below (a contact delta deep) or above (a near miss with
gap delta) the orbit's maximum. A contact that deep lasts ~2 sqrt(2 delta / |a|) ~ 5e-5 s,
far shorter than the integrator's steps (asserted), so a sign check at step ends would
miss every one of them; the core must find each one. The contact stiffness is made
negligible (kI = 1e-6) so that the contacts do not perturb the closed-form orbit: this
test is about detection; the contact physics is tested against SciPy elsewhere.
"""

import dataclasses
import math

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.model.parameters import ModelParams

OMEGA = 23.03
N_PERIODS = 60


def periodic_orbit(p, omega):
    F = p.m0e * omega**2
    den = (p.k - p.m * omega**2) ** 2 + (p.c * omega) ** 2
    a_s = F * (p.k - p.m * omega**2) / den
    a_c = -F * p.c * omega / den
    amp = math.hypot(a_s, a_c)
    phase = math.atan2(a_c, a_s)  # x = amp sin(w t + phase)
    return a_s, a_c, amp, phase


# kI = 1e-6 (far below the tested range) on purpose: the contact is then too soft to move the
# orbit, which stays the closed-form linear one, so every grazing is known exactly.
@pytest.mark.filterwarnings("ignore::impactosc.model.parameters.UntestedParameterWarning")
@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
@pytest.mark.parametrize("delta", [1e-9, 1e-7, 1e-5])
@pytest.mark.parametrize("side", ["contact", "near_miss"])
def test_every_grazing_event_found(rtol, delta, side):
    base = dataclasses.replace(ModelParams(), T=0.0, kI=1e-6, b=0.0)
    a_s, a_c, amp, phase = periodic_orbit(base, OMEGA)
    xI = amp - delta if side == "contact" else amp + delta
    p = dataclasses.replace(base, xI=xI)
    period = 2 * math.pi / OMEGA
    res = simulate(OMEGA, 0.0, N_PERIODS * period, x0=a_c, v0=a_s * OMEGA, params=p, rtol=rtol, atol=rtol * 1e-3)
    # exact maxima of the orbit: w t + phase = pi/2 + 2 pi i
    t_max = (math.pi / 2 - phase + 2 * math.pi * np.arange(N_PERIODS + 1)) / OMEGA
    t_max = t_max[(t_max > 0) & (t_max < N_PERIODS * period)]
    imp = res.events["impacts"]["t"]
    nm = res.events["near_misses"]
    mean_step = N_PERIODS * period / res.attrs["n_steps"]
    if side == "contact":
        # crossing of x = xI on the way up: amp sin(w t + phase) = xI
        t_cross = t_max - math.acos(xI / amp) / OMEGA
        assert len(imp) == len(t_max), f"{len(imp)} impacts for {len(t_max)} contacts of depth {delta}"
        # timing: the interpolant is exact to ~rtol * amp in x; divided by the crossing slope
        # sqrt(2 a delta) that is the bound below (factor 10 margin), never above 1e-3 s
        slope = OMEGA * math.sqrt(max(amp**2 - xI**2, 0.0))
        tol = min(1e-3, 10 * rtol * amp / slope + 1e-12)
        np.testing.assert_allclose(imp, t_cross, rtol=0, atol=tol)
        assert len(nm["t"]) == 0
        pen = res.events["penetrations"]["h"]
        assert len(pen) == len(t_max)
        np.testing.assert_allclose(pen, delta, rtol=0.05 + 10 * rtol * amp / delta)
        # the contacts are much shorter than the steps: a step-end sign check would miss them
        if delta <= 1e-7:
            contact_time = 2 * math.sqrt(2 * delta / (amp * OMEGA**2))
            assert mean_step > 3 * contact_time
    else:
        assert len(imp) == 0, f"{len(imp)} invented impacts for a gap of {delta}"
        assert len(nm["t"]) == len(t_max)
        np.testing.assert_allclose(nm["t"], t_max, rtol=0, atol=1e-6)
        np.testing.assert_allclose(nm["gap"], delta, rtol=0, atol=10 * rtol * amp + 1e-15)
