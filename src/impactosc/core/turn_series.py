"""The motion next to the deepest penetration (v = 0) as a series in w = |v|^n3.

Why: with v = sgn w^q (q = 1/n3 not an integer) the time and position are sums of terms
w^(i + j q), a lattice of exponents. DOP853 in w, whose steps assume integer powers, must
shrink its steps towards w = 0 (about nine attempts per contact on the chaotic scene, four
to six on either side of the turn). The series replaces those steps: it is built around the
turn point (t1, x1) level by level in z = w^q,

    t - t1 = sum_j z^j T_j(w),   x - x1 = sum_j z^j X_j(w),   T_j, X_j power series in w,

from dt/dw = sgn q w^(q-1) / a, dx/dw = q w^(2q-1) / a with a = M0(w) + delta(t, x, w) / m,
M0 = alpha + beta w the force frozen at the turn point (friction T sgn(v)), delta the rest,
expanded to third order in t - t1 and x - x1. Level j of m / a is a convolution of lower
levels divided by M0 (a two-term recurrence); integrating against w^(jq - 1) divides each
coefficient by jq + i. The levels decay like (w^q)^2 n1 / (2 a h1) (the contact's stiffness
acting on x - x1) and the terms in w like beta w / alpha, so a few levels of a few terms
reach 1e-12 relative at w ~ 0.2 for the chaotic scene's turns.

Dry friction enters as T sgn(v); its eps-layer (|v| ~ eps around the turn, where the
regularised friction T v / sqrt(v^2 + eps^2) is smaller) delays the motion by a time computed
analytically (:func:`layer_shift`, up to 2.3e-10 s net per contact on the chaotic scene): outside
the layer each side is the series of a turn point shifted by that delay. Its effect on x
(~ eps^2 ln(v / eps) m T / alpha^2, <= 7e-15 m) is added to leading order (:func:`layer_x`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.model.noise_kernel import harmonic_forcing
from impactosc.model.parameters import P_B, P_C, P_EPS, P_K, P_KI, P_M, P_M0E, P_N1, P_N2, P_N3, P_OMEGA, P_T, P_XI

# Terms in w kept at each level j = 0..5 (level j of m/a feeds T_{j+1} and X_{j+2}): chosen
# on the chaotic scene's turns against a 12-level, 48-term series, error 1.6e-12 relative in
# t - t1 at w = 0.2; the window (:func:`window`) keeps the estimated error below the tolerance.
TERMS = np.array([18, 18, 14, 14, 10, 10])
LEVELS = 5
WIDTH = 18
POW_T = 3  # powers (t - t1)^2, ^3 are kept up to this level (beyond: < 1e-14 relative) ...
POW_X = 5  # ... and (x - x1)^2 up to this one ((x - x1)^3 starts at level 6)
SAFETY = 4.0  # the error estimate (the next levels from the last two, the tail of level 1)
# was within a factor 2 of the true error on the chaotic scene's turns at w in [0.18, 0.28]
LAYER_TERMS = 12  # powers of beta |v|^n3 / alpha in the layer's correction; its tail out to w
# converges like (b w)^k, 0.2^12 ~ 4e-9 of a tail that is itself < 1e-2 of the correction
LAYER_MOMENTS = 8  # the layer's own terms fall like (b eps^n3)^k = 0.065^k (times moments that grow
# near s = 1, 7.7 at k = 5): the ninth is < 1e-8 of the first
LAYER_MIN = 30.0  # the eps-layer's correction to second order in T / |alpha| needs |alpha| > 30 T


@njit(cache=True)
def applies(p, field_is_contact):
    """Can the series run here? Harmonic forcing (its derivatives in t), the contact in front of
    any second stop, a damping b |v|^n3 with 0 < n3 < 1, and a regularised friction."""
    return (
        field_is_contact
        and harmonic_forcing(p)
        and p[P_B] > 0.0
        and 0.0 < p[P_N3] < 1.0
        and p[P_EPS] > 0.0
        and p[P_T] >= 0.0
    )


@njit(cache=True)
def work():
    """The coefficient arrays of one series (T, X, m/a, delta, (t-t1)^2, (t-t1)^3, (x-x1)^2) and
    the eps-layer's moments (they depend on n3 only: computed once per contact, row 7)."""
    c = np.zeros((8, LEVELS + 1, WIDTH))
    c[7, 1, 0] = -1.0  # the moments are not there yet
    return c


@njit(cache=True, inline="always")
def _conv(a, b, out, n, f):
    """out += f a b, the first n terms."""
    for i in range(n):
        acc = 0.0
        for lv in range(i + 1):
            acc += a[lv] * b[i - lv]
        out[i] += f * acc


@njit(cache=True)
def frozen(p, sig, t1, x1):
    """(alpha, beta): m a at the turn point on side sig (+1: v > 0) is alpha + beta w."""
    h1 = x1 - p[P_XI]
    w_f = p[P_OMEGA]
    s1 = p[P_M0E] * w_f * w_f * math.sin(w_f * t1) - p[P_K] * x1 - p[P_KI] * h1 ** p[P_N1]
    return s1 - sig * p[P_T], -sig * p[P_B] * p[P_KI] * h1 ** p[P_N2]


@njit(cache=True)
def build(p, sig, t1, x1, c):
    """Fill c with the series of side sig around the turn point (t1, x1); returns (alpha, beta)."""
    m, k, visc, kI, b, n1, n2 = p[P_M], p[P_K], p[P_C], p[P_KI], p[P_B], p[P_N1], p[P_N2]
    q = 1.0 / p[P_N3]
    w_f = p[P_OMEGA]
    amp = p[P_M0E] * w_f * w_f
    h1 = x1 - p[P_XI]
    sn, cs = math.sin(w_f * t1), math.cos(w_f * t1)
    hn1, hn2 = h1**n1, h1**n2
    alpha = amp * sn - k * x1 - kI * hn1 - sig * p[P_T]
    beta = -sig * b * kI * hn2
    # Taylor coefficients of delta in (t - t1) and (x - x1)
    f1, f2, f3 = amp * w_f * cs, -0.5 * amp * w_f * w_f * sn, -amp * w_f * w_f * w_f * cs / 6.0
    s1 = -k - kI * n1 * hn1 / h1
    s2 = -kI * 0.5 * n1 * (n1 - 1.0) * hn1 / (h1 * h1)
    g1 = beta * n2 / h1  # of -sig b kI h^n2 w
    g2 = beta * 0.5 * n2 * (n2 - 1.0) / (h1 * h1)
    tc, xc, r, d, t2, t3, x2 = c[0], c[1], c[2], c[3], c[4], c[5], c[6]
    for row in (2, 4, 5, 6):  # the rows sums accumulate into
        c[row, :, :] = 0.0
    ia = 1.0 / alpha
    for j in range(LEVELS + 1):
        n = TERMS[j]
        rj = r[j]
        if j == 0:
            rj[0] = m
        for lv in range(1, j):
            _conv(d[lv], r[j - lv], rj, n, 1.0)
        if j > 0:  # d_j r_0 = m d_j / (alpha + beta w): a recurrence, not a convolution
            y = 0.0
            for i in range(n):
                y = (d[j, i] - beta * y) * ia
                rj[i] += m * y
        y = 0.0
        for i in range(n):  # rj = -(sum of products) / (alpha + beta w), m at level 0
            y = ((rj[i] if j == 0 else -rj[i]) - beta * y) * ia
            rj[i] = y
        jj = j + 1
        if jj > LEVELS:
            break
        nn = TERMS[jj]
        for i in range(nn):
            tc[jj, i] = sig * q * r[j, i] / (jj * q + i)
            if jj >= 2:
                xc[jj, i] = q * r[jj - 2, i] / (jj * q + i)
        # the powers' level jj (products of two levels: each pair once, doubled)
        if jj <= POW_T:
            for lv in range(1, jj // 2 + 1):
                _conv(tc[lv], tc[jj - lv], t2[jj], nn, 1.0 if 2 * lv == jj else 2.0)
            for lv in range(1, jj - 1):
                _conv(tc[lv], t2[jj - lv], t3[jj], nn, 1.0)
        if jj <= POW_X:
            for lv in range(2, jj // 2 + 1):
                _conv(xc[lv], xc[jj - lv], x2[jj], nn, 1.0 if 2 * lv == jj else 2.0)
        dj = d[jj]
        for i in range(nn):
            dj[i] = f1 * tc[jj, i] + f2 * t2[jj, i] + f3 * t3[jj, i] + s1 * xc[jj, i] + s2 * x2[jj, i]
            if i > 0:
                dj[i] += g1 * xc[jj, i - 1] + g2 * x2[jj, i - 1]
        if jj == 1:
            dj[0] -= visc * sig
    return alpha, beta


@njit(cache=True)
def _level(c, comp, j, w):
    s = 0.0
    for i in range(TERMS[j] - 1, -1, -1):
        s = s * w + c[comp, j, i]
    return s


@njit(cache=True)
def evaluate(c, q, w):
    """(t - t1, x - x1, estimated relative error of t - t1) at w."""
    z = w**q
    tau = 0.0
    xi = 0.0
    l2 = l3 = l4 = l5 = 0.0
    for j in range(LEVELS, 0, -1):
        st = _level(c, 0, j, w)
        tau = (tau + st) * z
        xi = (xi + _level(c, 1, j, w)) * z
        if j == 5:
            l5 = abs(st)
        elif j == 4:
            l4 = abs(st)
        elif j == 3:
            l3 = abs(st)
        elif j == 2:
            l2 = abs(st)
    if tau == 0.0:
        return tau, xi, math.inf
    # the next levels, from the ratio of the last two of each parity; the tail of level 1
    z2 = z * z
    est = z2 * z2 * z * (z2 * l5 * l5 / max(l3, 1e-300) + z * l4 * l4 / max(l2, 1e-300))
    est += abs(c[0, 1, TERMS[1] - 1]) * w ** (TERMS[1] - 1) * z
    return tau, xi, SAFETY * est / abs(tau)


@njit(cache=True)
def _moment(s):
    """int_0^inf u^s (1 - u / sqrt(1 + u^2)) du for -1 < s < 1 (by parts, a Beta function)."""
    return math.gamma(1.0 + 0.5 * s) * math.gamma(0.5 * (1.0 - s)) / (2.0 * (s + 1.0) * math.gamma(1.5))


@njit(cache=True)
def layer_shift(p, sig, alpha, beta, w, c):
    """t (regularised friction) - t (T sgn(v)) at w on side sig, both from the same turn point.

    The friction differs by T psi(v), psi = sgn(v) - v / sqrt(v^2 + eps^2), over |v| ~ eps, so
    m dv / (M + T psi) differs from m dv / M by sum_n m (-T psi)^n / M^(n+1); with
    M = alpha + beta |v|^n3 expanded in powers of |v|^n3 each term is a moment of psi^n (Beta
    functions; convergent while k n3 < 1), minus the part of psi beyond w (~ eps^2 / (2 v^2))."""
    m, tf, eps, n3 = p[P_M], p[P_T], p[P_EPS], p[P_N3]
    mom = c[7, 0]
    if c[7, 1, 0] < 0.0:  # int psi0 u^s du and int psi0^2 u^s du at s = k n3 (u in units of eps)
        for k in range(LAYER_MOMENTS):
            s = k * n3
            mom[k] = _moment(s)
            if k < 3:
                mom[LAYER_MOMENTS + k] = 2.0 * mom[k] - 0.5 * math.pi / math.cos(0.5 * math.pi * s)
        c[7, 1, 0] = 1.0
    v = w ** (1.0 / n3)
    r = -beta * eps**n3 / alpha  # the layer's own terms, ~ b eps^n3
    x = -beta * w / alpha  # and those of its tail out to w, ~ b w
    first = 0.0  # int_0^v psi0 / M^2 dv times alpha^2 / eps
    second = 0.0  # int_0^inf psi0^2 / M^3 dv times alpha^3 / eps
    g = 1.0
    gx = eps / (2.0 * v)
    for k in range(LAYER_TERMS):
        s = k * n3
        # the moment to infinity less the part beyond v (psi0 ~ eps^2 / (2 u^2) there); both
        # continued analytically past s = 1, where their poles cancel
        first -= (k + 1) * gx / (1.0 - s)
        if k < LAYER_MOMENTS:
            first += (k + 1) * g * mom[k]
            if k < 3:
                second += 0.5 * (k + 1) * (k + 2) * g * mom[LAYER_MOMENTS + k]
        g *= r
        gx *= x
    third = 5.0 - 1.5 * math.pi  # int psi0^3 dv / eps
    a = tf / alpha
    return -m * eps / alpha * (a * first - sig * a * a * second + a * a * a * third)


@njit(cache=True)
def layer_x(p, sig, alpha, w):
    """x (regularised friction) - x (T sgn(v)) at w on side sig, from the same turn point: the
    layer's extra time weighted by v, -sig m T / alpha^2 int_0^v u psi0 du, to leading order
    (the integral grows like eps^2 ln(v / eps) / 2: ~7e-15 m on the periodic scene's slow turns)."""
    eps = p[P_EPS]
    v = w ** (1.0 / p[P_N3])
    moment = 0.5 * eps * eps * (math.asinh(v / eps) - v / (v + math.sqrt(v * v + eps * eps)))
    return -sig * p[P_M] * p[P_T] * moment / (alpha * alpha)


@njit(cache=True)
def usable(p, alpha, beta):
    """The series and the layer's correction hold: a decelerating force at the turn well above
    the friction, and the frozen force's zero beyond w = 1."""
    return alpha < 0.0 and -alpha > LAYER_MIN * p[P_T] and abs(beta) < -alpha


@njit(cache=True)
def turn_point(p, tc, xc, wc, tol, c):
    """The turn point (t1, x1) whose series (side v > 0) passes through (tc, xc) at w = wc.

    The series depends on (t1, x1) weakly (relatively ~ n1 (x - x1) / h1): start from the
    leading terms frozen at (tc, xc) (x1 to ~1e-4 of x - x1), build the series there and correct
    t1 for the guess's error to first order. Returns (ok, t1 - tc, x1)."""
    q = 1.0 / p[P_N3]
    if not tc == tc or xc - p[P_XI] <= 0.0:
        return False, 0.0, xc
    alpha, beta = frozen(p, 1.0, tc, xc)
    if not usable(p, alpha, beta):
        return False, 0.0, xc
    # leading terms: t - t1 ~ q m sum r^i w^(q+i)/(alpha (q+i)), x - x1 likewise with 2q
    z = wc**q
    rr = -beta / alpha * wc
    g = p[P_M] / alpha
    tau = 0.0
    xi = 0.0
    for i in range(TERMS[1]):
        tau += g / (q + i)
        xi += g / (2.0 * q + i)
        g *= rr
    dt1 = -q * z * tau
    x1g = xc - q * z * z * xi
    alpha, beta = build(p, 1.0, tc + dt1, x1g, c)
    if not usable(p, alpha, beta) or x1g - p[P_XI] <= 0.0:
        return False, 0.0, xc
    tau, xi, err = evaluate(c, q, wc)
    x1 = xc - xi
    # the guess's x1 was off by x1 - x1g (~1e-4 of x - x1): t - t1 depends on x1 through alpha
    # and beta mostly, d/dx1 of m / (alpha + beta w) = -(alpha' + beta' w) m / (alpha + beta w)^2
    h1 = x1g - p[P_XI]
    da = -p[P_K] - p[P_KI] * p[P_N1] * h1 ** (p[P_N1] - 1.0)
    db = beta * p[P_N2] / h1
    ia = 1.0 / alpha
    u = 0.0
    r0 = 0.0
    acc = 0.0
    wi = 1.0
    for i in range(TERMS[0]):
        r1 = c[2, 0, i]
        u = ((da * r1 + db * r0) - beta * u) * ia
        acc += u * wi / (q + i)
        r0 = r1
        wi *= wc
    dtau_dx1 = -q * z * acc
    dt1 = -tau - dtau_dx1 * (x1 - x1g)
    return err <= tol, dt1 - layer_shift(p, 1.0, alpha, beta, wc, c), x1 - layer_x(p, 1.0, alpha, wc)


@njit(cache=True)
def restitution(p, t1, x1, w_end, tol, c):
    """From the turn point (t1, x1) down the side v < 0: the largest w <= w_end at which the
    series' estimated error is within tol, and the state there. Returns (ok, w, t - t1, x - x1).

    Past the eps-layer the motion is the series' (friction T sgn(v)) from a turn point delayed by
    the layer's shift: the series is built there (the forcing has moved on by then: ~1e-4 of the
    shift for the slow turns of the periodic scene, 4e-13 s), and the shift added."""
    q = 1.0 / p[P_N3]
    alpha, beta = frozen(p, -1.0, t1, x1)
    if not usable(p, alpha, beta):
        return False, 0.0, 0.0, 0.0
    # the law's cut (its bracket h^n1 - b h^n2 w reaches 0) is an event the series must not
    # pass: stay below 0.9 of it (x - x1 ~ 1e-8 of h there moves it by far less)
    w_end = min(w_end, 0.9 * (x1 - p[P_XI]) ** (p[P_N1] - p[P_N2]) / p[P_B])
    delay = layer_shift(p, -1.0, alpha, beta, min(w_end, 0.2), c)
    alpha, beta = build(p, -1.0, t1 + delay, x1, c)
    # the error grows roughly like the next level, ~ w^(6q): aim at tol from a first probe
    w = min(w_end, 0.2)
    tau, xi, err = evaluate(c, q, w)
    for _ in range(4):
        if err <= tol and (w == w_end or err > 0.1 * tol):
            break
        f = (tol / max(err, 1e-300)) ** (1.0 / (6.0 * q))
        w = min(w_end, w * min(max(f, 0.5), 1.5) * (0.97 if err > tol else 1.0))
        tau, xi, err = evaluate(c, q, w)
    if not err <= tol:
        return False, 0.0, 0.0, 0.0
    return True, w, tau + layer_shift(p, -1.0, alpha, beta, w, c), xi + layer_x(p, -1.0, alpha, w)
