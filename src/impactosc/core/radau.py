"""Implicit Radau IIA (order 5) step for the stiff sticking / slow-reversal phases.

Near v = 0 the regularised friction has slope T/eps (time constant m eps / T ~ 1.4e-5 s);
while the cart sticks, an explicit method would be held to steps of that size for the
whole phase. Radau IIA is L-stable and stiffly accurate, so it follows the slow creep
manifold with steps set by accuracy alone. Error is estimated by step doubling (one step
of h against two of h/2), which needs no extra tableau and is reliable for a 2-D system.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core.layout import C_NEWTON, C_RHS
from impactosc.model.equations import accel_any, jacobian

_S6 = math.sqrt(6.0)
RA = np.array(
    [
        [(88.0 - 7.0 * _S6) / 360.0, (296.0 - 169.0 * _S6) / 1800.0, (-2.0 + 3.0 * _S6) / 225.0],
        [(296.0 + 169.0 * _S6) / 1800.0, (88.0 + 7.0 * _S6) / 360.0, (-2.0 - 3.0 * _S6) / 225.0],
        [(16.0 - _S6) / 36.0, (16.0 + _S6) / 36.0, 1.0 / 9.0],
    ]
)
RC = np.array([(4.0 - _S6) / 10.0, (4.0 + _S6) / 10.0, 1.0])
MAX_NEWTON = 12


@njit(cache=True)
def _lu_solve_inplace(Mat, rhs):
    """Gaussian elimination with partial pivoting on a small dense system (overwrites both)."""
    n = rhs.shape[0]
    for col in range(n):
        piv = col
        best = abs(Mat[col, col])
        for r in range(col + 1, n):
            if abs(Mat[r, col]) > best:
                best = abs(Mat[r, col])
                piv = r
        if best == 0.0:
            return False
        if piv != col:
            for j in range(n):
                tmp = Mat[col, j]
                Mat[col, j] = Mat[piv, j]
                Mat[piv, j] = tmp
            tmp = rhs[col]
            rhs[col] = rhs[piv]
            rhs[piv] = tmp
        for r in range(col + 1, n):
            fac = Mat[r, col] / Mat[col, col]
            if fac != 0.0:
                for j in range(col, n):
                    Mat[r, j] -= fac * Mat[col, j]
                rhs[r] -= fac * rhs[col]
    for r in range(n - 1, -1, -1):
        acc = rhs[r]
        for j in range(r + 1, n):
            acc -= Mat[r, j] * rhs[j]
        rhs[r] = acc / Mat[r, r]
    return True


@njit(cache=True)
def radau_step(p, field, t, x, v, h, rtol, atol, work, cnt):
    """One Radau IIA step of size h; returns (ok, x_new, v_new). cnt[C_RHS] counts RHS calls.

    Newton uses the Jacobian refreshed at each iteration (the friction slope changes by
    orders of magnitude across the creep band, so a frozen Jacobian converges poorly).
    """
    Z = work[0]  # 3 stages x 2 components, flattened into 6
    Mat = work[1:7]
    rhs = work[7]
    sx = atol + rtol * abs(x)
    sv = atol + rtol * abs(v)
    # Attempt 0 uses the tangent Jacobian (quadratic convergence). Newton on the
    # Hunt-Crossley term sgn(v)|v|^n3 diverges when that term dominates near v = 0 (as on
    # x^(1/3)), which used to collapse the step size while the cart sticks in contact;
    # attempt 1 then uses its chord slope through v = 0, a contraction (see model.jacobian).
    for attempt in range(2):
        for i in range(6):
            Z[i] = 0.0
        for _it in range(MAX_NEWTON):
            for i in range(6):
                rhs[i] = 0.0
                for j in range(6):
                    Mat[i, j] = 1.0 if i == j else 0.0
            # residual G_i = Z_i - h sum_j a_ij f(t + c_j h, y + Z_j); Jacobian blocks per stage j
            for j in range(3):
                xj = x + Z[2 * j]
                vj = v + Z[2 * j + 1]
                fx = vj
                fv = accel_any(p, field, t + RC[j] * h, xj, vj)
                cnt[C_RHS] += 1
                jx, jv = jacobian(p, field, t + RC[j] * h, xj, vj, attempt == 1)
                for i in range(3):
                    a = RA[i, j] * h
                    rhs[2 * i] += a * fx
                    rhs[2 * i + 1] += a * fv
                    # d f_x / d Z_j = (0, 1); d f_v / d Z_j = (jx, jv)
                    Mat[2 * i, 2 * j + 1] -= a
                    Mat[2 * i + 1, 2 * j] -= a * jx
                    Mat[2 * i + 1, 2 * j + 1] -= a * jv
            for i in range(6):
                rhs[i] -= Z[i]  # rhs = -G
            if not _lu_solve_inplace(Mat, rhs):
                break
            dn = 0.0
            for i in range(6):
                Z[i] += rhs[i]
                s = sx if i % 2 == 0 else sv
                dn = max(dn, abs(rhs[i]) / s)
            cnt[C_NEWTON] += 1
            if not (dn == dn) or dn > 1e12:
                break
            if dn < 1e-3:
                return True, x + Z[4], v + Z[5]
    return False, x, v


@njit(cache=True)
def doubled_step(p, field, t, x, v, h, rtol, atol, work, cnt):
    """Step h as two half steps, with the error estimated against one full step.

    Returns (ok, x_new, v_new, err) with err the scaled RMS error of the half-step result.
    """
    ok1, xf, vf = radau_step(p, field, t, x, v, h, rtol, atol, work, cnt)
    if not ok1:
        return False, x, v, math.inf
    ok2, xh, vh = radau_step(p, field, t, x, v, 0.5 * h, rtol, atol, work, cnt)
    if not ok2:
        return False, x, v, math.inf
    ok3, x2, v2 = radau_step(p, field, t + 0.5 * h, xh, vh, 0.5 * h, rtol, atol, work, cnt)
    if not ok3:
        return False, x, v, math.inf
    sx = atol + rtol * max(abs(x), abs(x2))
    sv = atol + rtol * max(abs(v), abs(v2))
    err = math.sqrt((((x2 - xf) / sx) ** 2 + ((v2 - vf) / sv) ** 2) / 2.0) / 31.0
    return True, x2, v2, err
