"""Levenberg-Marquardt for multiple shooting: shared parameters, one start state per window.

Why our own and not scipy.optimize.least_squares: the Jacobian has the arrow structure of
multiple shooting (each window's samples depend on its own two start-state entries and on the
P shared parameters), so the normal equations are solved by eliminating each window's 2 x 2
block (the Schur complement, as in bundle adjustment): a P x P system however many windows.
A dense solver would carry 2 x (number of windows) more columns.

The covariance of the shared parameters is s^2 (V - sum_j W_j^T U_j^-1 W_j)^-1, the inverse of
the information left for them once every window's state is fitted (the same elimination at
lambda = 0), with s^2 = RSS / (N - P - 2 n_windows) estimated from the residuals.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.identification.window_predictions import STATE_STEPS, Predictor

__all__ = ["FitResult", "carried_states", "fit_states", "fit"]


@dataclass
class FitResult:
    """Fitted theta and states, the covariance of theta[free], residual statistics."""

    theta: np.ndarray
    states: np.ndarray
    free: np.ndarray
    cov: np.ndarray  # of theta[free]
    rss: float
    n_samples: int
    dof: int
    iterations: int
    converged: bool
    window_rss: np.ndarray

    @property
    def s2(self) -> float:
        return self.rss / max(self.dof, 1)

    @property
    def stderr(self) -> np.ndarray:
        """Standard error of every theta entry (0 for fixed ones)."""
        se = np.zeros(self.theta.size)
        se[self.free] = np.sqrt(np.maximum(np.diag(self.cov), 0.0))
        return se

    @property
    def correlation(self) -> np.ndarray:
        d = np.sqrt(np.maximum(np.diag(self.cov), 0.0))
        d = np.where(d > 0, d, 1.0)
        return (self.cov / d[:, None]) / d[None, :]


def _window_rss(r, w):
    return np.add.reduceat(np.nan_to_num(r, nan=1e6) ** 2, w.offset) if w.size else np.zeros(0)


def _fit_state(pred, p, j, state, n, max_iter, tol):
    """One window's start state by a 2-parameter LM on its first n samples; (state, rss)."""
    w = pred.w
    yj = w.y[w.offset[j] : w.offset[j] + n]
    out, col = np.empty(n), np.empty(n)
    pred.window(p, j, state[0], state[1], out, n)
    rj = out - yj
    cost = float(rj @ rj) if np.all(np.isfinite(rj)) else np.inf
    lam = 1e-3
    for _ in range(max_iter):
        if not np.isfinite(cost):
            break
        A = np.empty((n, 2))
        for c, h in enumerate(STATE_STEPS):
            s = state.copy()
            s[c] += h
            pred.window(p, j, s[0], s[1], col, n)
            A[:, c] = (col - out) / h
        if not np.all(np.isfinite(A)):
            break
        g, U = A.T @ rj, A.T @ A
        for _ in range(12):
            trial = state + np.linalg.solve(U + lam * np.diag(np.diag(U) + 1e-30), -g)
            pred.window(p, j, trial[0], trial[1], col, n)
            rt = col - yj
            ct = float(rt @ rt) if np.all(np.isfinite(rt)) else np.inf
            if ct < cost:
                break
            lam *= 8
        else:
            break
        done = cost - ct <= tol * cost
        state, out, rj, cost, lam = trial, col.copy(), rt, ct, max(lam / 5, 1e-9)
        if done:
            break
    return state, cost


def fit_states(pred: Predictor, theta, states, *, close=None, max_iter=40, tol=1e-10) -> tuple[np.ndarray, np.ndarray]:
    """Each window's start state fitted alone (theta fixed); returns (states, per-window RSS).

    Why a growing horizon (the first quarter of the window, then half, then all of it): a
    start state guessed from a local polynomial is off by about a mm/s, which moves the
    window's later impacts so far that a fit to the whole window can settle on another
    trajectory; over the first quarter the same error is small, and each longer horizon starts
    from the shorter one's answer.  A guess already on a fitted trajectory (``close``, a mask:
    carried over from shorter windows by :func:`carried_states`) is fitted to the whole window
    at once.  The windows are independent here: each has its own damping.
    """
    w = pred.w
    states = states.copy()
    close = np.zeros(w.size, dtype=bool) if close is None else np.asarray(close, dtype=bool)
    p = pred._p(theta)
    rss = np.empty(w.size)
    for j in range(w.size):
        n = int(w.n[j])
        for part in (1,) if close[j] else (4, 2, 1):
            states[j], rss[j] = _fit_state(pred, p, j, states[j], max(8, n // part), max_iter, tol)
    return states, rss


def carried_states(fitted: Predictor, fitted_states, trusted, theta, windows) -> tuple[np.ndarray, np.ndarray]:
    """Guesses of the start states of ``windows`` from the trajectories fitted to other windows
    of the same records (``fitted``, with their states ``fitted_states``, at ``theta``): the
    state at each window's first sample, integrated from the fitted window that holds that
    sample.  Returns (states, close): the polynomial guess (windows.x0, v0) where no fitted
    window of the mask ``trusted`` holds the sample or its run failed, and the mask of the
    windows that got a carried one.

    Why: the next stage's windows start elsewhere (each at its own fastest free-flight sample),
    and a state on the fitted trajectory is far closer than a local polynomial's guess.
    """
    fw = fitted.w
    states = np.column_stack([windows.x0, windows.v0])
    close = np.zeros(windows.size, dtype=bool)
    p = fitted._p(theta)
    for j in range(windows.size):
        a = int(windows.start[j])
        holds = np.flatnonzero(trusted & (fw.record == windows.record[j]) & (fw.start <= a) & (a < fw.start + fw.n))
        if holds.size == 0:
            continue
        i = int(holds[0])
        n = a - int(fw.start[i])
        end = fitted_states[i] if n == 0 else fitted.window(p, i, *fitted_states[i], np.empty(n), n)
        if np.all(np.isfinite(end)):
            states[j], close[j] = end, True
    return states, close


def _schur(A, B, r, w, lam):
    """Reduced system for the shared step; returns (M, rhs, per-window (Uinv, W, gA))."""
    P = B.shape[1]
    M = B.T @ B
    rhs = -(B.T @ r)
    blocks = []
    for j in range(w.size):
        sl = slice(w.offset[j], w.offset[j] + w.n[j])
        Aj, Bj, rj = A[sl], B[sl], r[sl]
        U = Aj.T @ Aj
        U = U + lam * np.diag(np.diag(U))
        Uinv = np.linalg.inv(U)
        Wj = Aj.T @ Bj
        gA = Aj.T @ rj
        M -= Wj.T @ Uinv @ Wj
        rhs += Wj.T @ Uinv @ gA
        blocks.append((Uinv, Wj, gA))
    if P:
        M = M + lam * np.diag(np.diag(B.T @ B))
    return M, rhs, blocks


def _solve_scaled(M, rhs):
    """M^-1 rhs with Jacobi scaling (the parameters' units differ by 10 orders of magnitude)."""
    d = 1.0 / np.sqrt(np.maximum(np.diag(M), 1e-300))
    return d * np.linalg.lstsq(M * np.outer(d, d), d * rhs, rcond=1e-13)[0]


def _inverse_scaled(M):
    d = 1.0 / np.sqrt(np.maximum(np.diag(M), 1e-300))
    return np.linalg.pinv(M * np.outer(d, d), rcond=1e-13) * np.outer(d, d)


def _newton_gap(A, B, r, w, theta, idx, lower, upper, dof):
    """(cov, gap): the covariance of theta[idx] at the current point and the undamped
    Gauss-Newton step (projected onto the bounds) in units of the standard errors."""
    M0, rhs0, _ = _schur(A, B, r, w, 0.0)
    if not idx.size:
        return np.zeros((0, 0)), 0.0
    cov = _inverse_scaled(M0) * (float(r @ r) / max(dof, 1))
    step = np.clip(theta[idx] + _solve_scaled(M0, rhs0), lower[idx], upper[idx]) - theta[idx]
    se = np.sqrt(np.maximum(np.diag(cov), 1e-300))
    return cov, float(np.max(np.abs(step) / se))


def fit(
    pred: Predictor,
    theta0,
    states0,
    free,
    names,
    *,
    lower=None,
    upper=None,
    max_iter=60,
    rel_step_tol=0.05,
    progress=None,
) -> FitResult:
    """Shared parameters theta[free] and every window's state by Levenberg-Marquardt.

    Steps are projected onto [lower, upper].  Converged when the undamped Gauss-Newton step
    from the current point moves no parameter by more than ``rel_step_tol`` of its standard
    error: the distance still to go, not the last (damped) step, which can be small far from
    the minimum.  ``progress(it, rss)`` is called after each iteration.
    """
    w = pred.w
    free = np.asarray(free, dtype=bool)
    theta, states = np.array(theta0, dtype=float), np.array(states0, dtype=float)
    lower = np.full(theta.size, -np.inf) if lower is None else lower
    upper = np.full(theta.size, np.inf) if upper is None else upper
    idx = np.flatnonzero(free)
    dof = int(w.y.size - idx.size - 2 * w.size)
    pr, _, A, _, B, _ = pred.jacobian(theta, states, free, names)
    r = pr - w.y
    cost = float(r @ r)
    lam, converged, it = 1e-3, False, 0
    for it in range(1, max_iter + 1):
        cov, gap = _newton_gap(A, B, r, w, theta, idx, lower, upper, dof)
        if gap <= rel_step_tol:
            converged = True
            break
        for _ in range(10):
            M, rhs, blocks = _schur(A, B, r, w, lam)
            th_new = theta.copy()
            if idx.size:
                th_new[idx] = np.clip(theta[idx] + _solve_scaled(M, rhs), lower[idx], upper[idx])
            dth = th_new[idx] - theta[idx]
            st_new = states.copy()
            for j, (Uinv, Wj, gA) in enumerate(blocks):
                st_new[j] = states[j] - Uinv @ (gA + Wj @ dth)
            r_new = pred.residuals(th_new, st_new)
            c_new = float(r_new @ r_new) if np.all(np.isfinite(r_new)) else np.inf
            if c_new < cost:
                break
            lam *= 6
        else:  # no step lowers the cost: the minimum to the precision of the runs
            break
        theta, states, cost = th_new, st_new, c_new
        lam = max(lam / 4, 1e-9)
        if progress is not None:
            progress(it, cost)
        pr, _, A, _, B, _ = pred.jacobian(theta, states, free, names)
        r = pr - w.y
    cov, gap = _newton_gap(A, B, r, w, theta, idx, lower, upper, dof)
    converged = converged or gap <= rel_step_tol
    return FitResult(theta, states, free, cov, cost, int(w.y.size), dof, it, converged, _window_rss(r, w))
