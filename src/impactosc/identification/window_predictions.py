"""The model's prediction of every window and its sensitivities, from the core.

Why the core and finite differences: the core is the model every figure is drawn with, event
split (contact onset and exit, v = 0, the Hunt-Crossley cut) so each window's samples are a
smooth function of its start state and of the parameters between grazings; differences of two
runs at rtol 1e-10 carry about 1e-13 m of integration noise against changes of 1e-9 m from the
steps below, a relative error near 1e-4 in each derivative, which Gauss-Newton does not feel.

Each window starts at its own (tau0, x0, v0) at its own w and is sampled at the record's
instants through the core's trajectory window (dense output, no interpolation of ours).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.core import driver as core
from impactosc.core.layout import N_COUNT, RUNNING, S_STATUS
from impactosc.identification.fitted_parameters import fill_array
from impactosc.identification.windows import WindowSet
from impactosc.model.parameters import P_B, P_N3, P_OMEGA, cut_is_line, new_contact_state

__all__ = ["Predictor", "STATE_STEPS", "relative_steps"]

#: Difference steps of the start state (x0 in m, v0 in m/s).
STATE_STEPS = (1e-8, 1e-6)
#: Relative difference step of the parameters (xI and n3 take absolute steps, below).
_REL_STEP = 1e-6
_ABS_STEP = {"n3": 1e-6, "xI": 1e-9}


def relative_steps(names, theta) -> np.ndarray:
    """Difference step of each parameter of theta (named ``names``)."""
    return np.array([_ABS_STEP.get(nm, _REL_STEP * max(abs(th), 1e-12)) for nm, th in zip(names, theta)])


def _cut_velocity(b, n3) -> float:
    """b^(-1/n3), the speed beyond which the Hunt-Crossley bracket turns negative; inf when it
    does not exist or lies beyond any speed (a small b with a small n3 overflows the power)."""
    if b <= 0.0 or n3 <= 0.0:
        return math.inf
    e = -math.log(b) / n3
    return math.exp(e) if e < 700.0 else math.inf


class Predictor:
    """Runs the core over a WindowSet for given parameters and start states.

    base : the core's parameter array of the base model (m, eps, n1, n2 and the fixed fields).
    Failed windows (a run that stops before its end) come back as NaN samples.
    """

    def __init__(self, windows: WindowSet, base: np.ndarray, m: float, *, rtol=1e-10, atol=1e-12, step_budget=1e5):
        self.w = windows
        self.base = base.copy()
        self.m = float(m)
        self.rtol, self.atol = float(rtol), float(atol)
        self.step_budget = float(step_budget)
        self.runs = 0

    def _p(self, theta):
        p = self.base.copy()
        fill_array(p, theta, self.m)
        return p

    def window(self, p, j, x0, v0, out, n=None):
        """The first n (default all) samples of window j from (x0, v0) into ``out``; returns the
        state (x, v) one sample interval after the last (where the next window starts).  NaN
        where the run failed."""
        w = self.w
        n = int(w.n[j]) if n is None else int(n)
        dt, tau0 = float(w.dt[j]), float(w.tau0[j])
        p[P_OMEGA] = w.omega[j]
        period = 2.0 * math.pi / w.omega[j]
        new_contact_state(p)  # a damping set per contact is set at its onset inside the window
        # the cut a run starts with, as the core's simulate sets it: a velocity where it is that line
        vcut = _cut_velocity(p[P_B], p[P_N3]) if cut_is_line(p) else math.inf
        st = core.initial_state(p, tau0, float(x0), float(v0), period, vcut, self.step_budget)
        cnt = np.zeros(N_COUNT, dtype=np.int64)
        rs = core.run_settings(tau0 + n * dt * (1 + 1e-12) + 1e-12, math.inf, self.rtol, self.atol, 0, period, tau0, dt)
        wx = np.full(n + 1, np.nan)
        wv = np.full(n + 1, np.nan)
        core.run(p, st, cnt, rs, np.empty((4, 4)), 0, wx, wv, 50_000_000)
        self.runs += 1
        if st[S_STATUS] != RUNNING:
            wx[:] = wv[:] = np.nan
        out[:n] = wx[:n]
        return wx[n], wv[n]

    def predict(self, theta, states, ends=False):
        """Model samples of every window, concatenated like WindowSet.y; with ``ends`` also the
        end states (windows x 2, see :meth:`window`)."""
        p = self._p(theta)
        w = self.w
        out = np.empty(w.y.size)
        E = np.empty((w.size, 2))
        for j in range(w.size):
            E[j] = self.window(p, j, states[j, 0], states[j, 1], out[w.offset[j] : w.offset[j] + w.n[j]])
        return (out, E) if ends else out

    def residuals(self, theta, states) -> np.ndarray:
        return self.predict(theta, states) - self.w.y

    def jacobian(self, theta, states, free, names):
        """(pred, E, A, Phi, B, G): predictions and end states, and their forward differences
        with respect to each window's start state (A: N x 2, Phi: windows x 2 x 2) and to
        theta[free] (B: N x P, G: windows x 2 x P).

        Forward differences (the steps of STATE_STEPS and relative_steps); each window's rows
        of A are its own start state's columns (the block structure of multiple shooting).
        """
        w = self.w
        pred, E = self.predict(theta, states, ends=True)
        A = np.empty((w.y.size, 2))
        Phi = np.empty((w.size, 2, 2))
        p = self._p(theta)
        col = np.empty(w.y.size)
        for j in range(w.size):
            sl = slice(w.offset[j], w.offset[j] + w.n[j])
            for c, h in enumerate(STATE_STEPS):
                s = states[j].copy()
                s[c] += h
                e = self.window(p, j, s[0], s[1], col[sl])
                A[sl, c] = (col[sl] - pred[sl]) / h
                Phi[j, :, c] = (np.array(e) - E[j]) / h
        idx = np.flatnonzero(free)
        steps = relative_steps([names[i] for i in idx], theta[idx])
        B = np.empty((w.y.size, idx.size))
        G = np.empty((w.size, 2, idx.size))
        for k, (i, h) in enumerate(zip(idx, steps)):
            th = theta.copy()
            th[i] += h
            pk, Ek = self.predict(th, states, ends=True)
            B[:, k] = (pk - pred) / h
            G[:, :, k] = (Ek - E) / h
        return pred, E, A, Phi, B, G
