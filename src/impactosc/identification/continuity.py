"""Multiple shooting with continuity: consecutive windows joined into one trajectory.

Why: with free start states every window costs two parameters, and a few hundred windows of
a few hundred noisy samples each bias the shared parameters (the incidental-parameter problem
of maximum likelihood: each window's state estimate is noisy, the model is nonlinear in it,
and the small bias each window lends to theta adds up while theta's standard error shrinks).
Measured on a chaotic record (w = 40.86, 60 s, 5 um noise, six noise draws): free windows of
2 forcing periods put k/m 1.9 standard errors low on average, of 4 periods 0.7.  Bock's
multiple shooting removes it: the end state of window j must equal the start state of window
j + 1 (where they are contiguous in a record), so a chain of windows is one trajectory of
the model with two free start entries, while each window is still integrated only from its
own start (the expanding directions of a chaotic attractor never act over more than a window).

Each Gauss-Newton step solves the equality-constrained linear least-squares problem

    min |r + A ds + B dtheta|^2   s.t.   e_j + Phi_j ds_j + G_j dtheta - s_{j+1} - ds_{j+1} = 0

through its sparse KKT system (scipy.sparse LU), with the unknowns scaled by the diagonal of
J^T J.  The covariance of theta is the theta block of the inverse KKT matrix times s^2 =
RSS / (N - P - 2 (windows - links)).  It starts from the free-window fit, where the
continuity gaps are already small (micrometres, mm/s), so full steps converge in a few.

A window whose runs for the differences did not all finish (the core stopped one at a start
state or parameter a step away: its sensitivities are NaN) sits out the step it would spoil:
one NaN in the KKT matrix makes its LU report "Factor is exactly singular" and ends the fit.
Its rows are zeroed and its joins dropped for that step (:func:`_finite_step`), so it neither
pulls theta nor moves; a parameter without effect (a zero column) needs nothing of the kind,
the 1e-10 on the scaled diagonal keeps it solvable.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from impactosc.identification.least_squares import FitResult, _window_rss
from impactosc.identification.window_predictions import Predictor
from impactosc.identification.windows import WindowSet

__all__ = ["links", "fit_continuous", "GAP_LIMIT"]

#: Windows whose ends miss by more than this many noise stds at the start are not joined.
GAP_LIMIT = 20.0


def links(w: WindowSet) -> np.ndarray:
    """Indices j whose window j + 1 continues window j (same record, next sample)."""
    j = np.arange(w.size - 1)
    return j[(w.record[1:] == w.record[:-1]) & (w.start[1:] == w.start[:-1] + w.n[:-1])]


def _kkt(A, Phi, B, G, r, gaps, w, lk, lam):
    """The scaled KKT matrix (as an LU), its right-hand side and the column scale."""
    W, P, L = w.size, B.shape[1], lk.size
    nz = 2 * W + P
    rows, cols, vals = [], [], []

    def put(r0, c0, block):
        rr, cc = np.nonzero(np.ones_like(block, dtype=bool))
        rows.append(rr + r0)
        cols.append(cc + c0)
        vals.append(block.ravel())

    g = np.empty(nz)
    for j in range(W):
        sl = slice(w.offset[j], w.offset[j] + w.n[j])
        Aj, Bj = A[sl], B[sl]
        put(2 * j, 2 * j, Aj.T @ Aj)
        if P:
            cpl = Aj.T @ Bj
            put(2 * j, 2 * W, cpl)
            put(2 * W, 2 * j, cpl.T)
        g[2 * j : 2 * j + 2] = Aj.T @ r[sl]
    if P:
        put(2 * W, 2 * W, B.T @ B)
        g[2 * W :] = B.T @ r
    H = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nz, nz)).tocsr()
    diag = H.diagonal()
    d = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
    Dm = sp.diags(d)
    # + 1e-10: a column the data do not see at all (a parameter without effect) stays solvable
    Hs = Dm @ H @ Dm + (lam + 1e-10) * sp.identity(nz)
    crow, ccol, cval = [], [], []
    for k, j in enumerate(lk):
        for a in range(2):
            row = 2 * k + a
            crow += [row, row, row]
            ccol += [2 * j, 2 * j + 1, 2 * (j + 1) + a]
            cval += [Phi[j, a, 0], Phi[j, a, 1], -1.0]
            for q in range(P):
                crow.append(row)
                ccol.append(2 * W + q)
                cval.append(G[j, a, q])
    C = sp.coo_matrix((cval, (crow, ccol)), shape=(2 * L, nz)).tocsr() @ Dm
    rs = 1.0 / np.maximum(abs(C).max(axis=1).toarray().ravel(), 1e-300)
    Cs = sp.diags(rs) @ C
    K = sp.bmat([[Hs, Cs.T], [Cs, None]], format="csc")
    rhs = np.concatenate([-d * g, -rs * gaps.ravel()])
    return splu(K), rhs, d


def _finite_step(w: WindowSet, lk, r, E, A, Phi, B, G):
    """(r, A, Phi, B, G, lk) for the KKT system with every window whose residuals,
    sensitivities or end state are not all finite taken out: its rows zero and its joins
    (to and from it) dropped; the arrays themselves where every window is finite."""
    rows = np.isfinite(r) & np.all(np.isfinite(A), axis=1) & np.all(np.isfinite(B), axis=1)
    ok = np.logical_and.reduceat(rows, w.offset) if w.size else np.ones(0, dtype=bool)
    ok &= np.all(np.isfinite(Phi), axis=(1, 2)) & np.all(np.isfinite(G), axis=(1, 2)) & np.all(np.isfinite(E), axis=1)
    if ok.all():
        return r, A, Phi, B, G, lk
    bad = np.repeat(~ok, w.n)
    r = np.where(bad, 0.0, r)
    A = np.where(bad[:, None], 0.0, A)
    B = np.where(bad[:, None], 0.0, B)
    Phi = np.where(ok[:, None, None], Phi, 0.0)
    G = np.where(ok[:, None, None], G, 0.0)
    return r, A, Phi, B, G, lk[ok[lk] & ok[lk + 1]]


def fit_continuous(
    pred: Predictor,
    theta0,
    states0,
    free,
    names,
    *,
    lower=None,
    upper=None,
    max_iter=15,
    rel_step_tol=0.25,
    progress=None,
) -> FitResult:
    """Theta and the window states with the continuity conditions of :func:`links` (see the
    module docstring).  Converged when a full step moves no parameter by more than
    ``rel_step_tol`` standard errors and the gaps are below a hundredth of the noise."""
    w = pred.w
    free = np.asarray(free, dtype=bool)
    idx = np.flatnonzero(free)
    theta, states = np.array(theta0, dtype=float), np.array(states0, dtype=float)
    lower = np.full(theta.size, -np.inf) if lower is None else lower
    upper = np.full(theta.size, np.inf) if upper is None else upper
    lk = links(w)
    W, P = w.size, idx.size
    dof = int(w.y.size - P - 2 * (W - lk.size))
    converged, it = False, 0
    pr, E, A, Phi, B, G = pred.jacobian(theta, states, free, names)
    r = pr - w.y
    cost0 = cost = float(r @ r)
    noise = np.sqrt(cost / max(dof, 1))
    # a join whose gap is far beyond the noise is a window that found another trajectory: no link
    lk = lk[np.abs(E[lk, 0] - states[lk + 1, 0]) < GAP_LIMIT * noise]
    dof = int(w.y.size - P - 2 * (W - lk.size))
    for it in range(1, max_iter + 1):
        rf, Af, Phif, Bf, Gf, lkf = _finite_step(w, lk, r, E, A, Phi, B, G)
        gaps = E[lkf] - states[lkf + 1]
        lu, rhs, d = _kkt(Af, Phif, Bf, Gf, rf, gaps, w, lkf, 0.0)
        z = d * lu.solve(rhs)[: 2 * W + P]
        se = _stderr(lu, d, W, P, cost / max(dof, 1))
        gap = float(np.max(np.abs(gaps[:, 0]), initial=0.0))
        if progress is not None:
            progress(it, cost, gap)
        if np.all(np.abs(z[2 * W :]) <= rel_step_tol * se) and gap < 1e-2 * noise:
            converged = True
            break
        for _ in range(6):  # full step, else halved: the gaps may not open, the fit may not collapse
            th_new = theta.copy()
            th_new[idx] = np.clip(theta[idx] + z[2 * W :], lower[idx], upper[idx])
            st_new = states + z[: 2 * W].reshape(W, 2)
            pr_new, E_new = pred.predict(th_new, st_new, ends=True)
            r_new = pr_new - w.y
            c_new = float(r_new @ r_new) if np.all(np.isfinite(r_new)) else np.inf
            g_new = float(np.max(np.abs(E_new[lk, 0] - st_new[lk + 1, 0]), initial=0.0))
            if c_new < 1.5 * cost0 and g_new <= max(gap, 10 * noise):
                break
            z = z / 2
        else:
            break
        theta, states = th_new, st_new
        pr, E, A, Phi, B, G = pred.jacobian(theta, states, free, names)
        r = pr - w.y
        cost = float(r @ r)
    # the Jacobian in hand is at (theta, states) on every way out of the loop
    rf, Af, Phif, Bf, Gf, lkf = _finite_step(w, lk, r, E, A, Phi, B, G)
    lu, _, d = _kkt(Af, Phif, Bf, Gf, rf, E[lkf] - states[lkf + 1], w, lkf, 0.0)
    cov = _covariance(lu, d, W, P) * (cost / max(dof, 1))
    converged = converged and bool(np.max(np.abs(E[lk, 0] - states[lk + 1, 0]), initial=0.0) < 1e-2 * noise)
    return FitResult(theta, states, free, cov, cost, int(w.y.size), dof, it, converged, _window_rss(r, w))


def _covariance(lu, d, W, P):
    """The theta block of the inverse (unscaled) KKT matrix."""
    if not P:
        return np.zeros((0, 0))
    n = lu.shape[0]
    E = np.zeros((n, P))
    E[2 * W + np.arange(P), np.arange(P)] = 1.0
    X = lu.solve(E)[2 * W : 2 * W + P]
    dt = d[2 * W :]
    return X * np.outer(dt, dt)


def _stderr(lu, d, W, P, s2):
    return np.sqrt(np.maximum(np.diag(_covariance(lu, d, W, P)) * s2, 1e-300))
