"""Taylor steps against the core's DOP853 steps and heyoka, piece by piece (benchmark_taylor).

Why: before a Taylor core is built, measure what it can gain. Three pieces of the paper's
scenes, each integrated to its end by (1) the core's own DOP853 step (dop853.step in its
variable, with Hairer's step-size rule), (2) our numba Taylor stepper (taylor_series) at
several orders, (3) heyoka on the same transformed equations (the compiled Taylor reference,
LLVM, when installed). Each piece's end is compared with SciPy DOP853 at rtol 1e-13 in time
(an independent reference; in the transformed variables only the piece's end is compared).

* free flight in time over the stretch between two friction bands (|v| > 1e3 eps) of the
  scene without an obstacle (w = 40.86);
* the turn at the deepest penetration in s = -|v|^n3, from v = 0.7 v0 to v = 0, after the
  impact at t = 0.7086 s with v0 = 0.195 m/s (the chaotic scene);
* a free-flight reversal through the friction band, s = -asinh(v/eps) from v = 1e3 eps to
  -1e3 eps.

:func:`projection` scales the core's step attempts per forcing period on the chaotic scene
(its counters per variable) by each piece's measured time per attempt: what the core's time
per period would become with the faster method on every piece of that kind (contact onset and
exit in sqrt(x - xI) counted as the turn).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from impactosc.core import dop853, vector_fields
from impactosc.core.layout import TIME, UVEL, WVEL
from impactosc.model.equations import CONTACT, FREE
from impactosc.model.parameters import ModelParams
from impactosc_bench.scipy_reference import model_forces
from impactosc_bench.taylor_series import BAND_PIECE, PIECE_NAMES, TIME_PIECE, TURN_PIECE, integrate_piece

OMEGA = 40.86
IMPACT_T, IMPACT_V = 0.7086, 0.195  # an impact of the chaotic scene
TURN_START = 0.7  # v / v0 at which the measured turn piece starts in |v|^n3 (the core's switch when it was measured)
BAND = 1e3  # |v| / eps of the friction band's edges (pieces.U_BAND)
REFERENCE = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-16}


@dataclass(frozen=True)
class Piece:
    """A piece: its kind, variable range, start state and SciPy's end state (a_end, b_end)."""

    kind: int
    params: ModelParams
    s0: float
    s1: float
    sgn: float
    tref: float
    a0: float
    b0: float
    a_end: float
    b_end: float
    v0: float  # velocity at the start (the DOP853 step needs it)


def _until(params, contact, t0, y0, t_max, level, direction=0):
    """SciPy from (t0, y0) to where v crosses `level` (in `direction`): (t, x, v) there."""
    from scipy.integrate import solve_ivp

    def event(t, y):
        return y[1] - level

    event.terminal, event.direction = True, direction
    external, contact_force, _ = model_forces(params, OMEGA)

    def rhs(t, y):
        force = external(t, y[0], y[1]) - (contact_force(y[0], y[1]) if contact else 0.0)
        return [y[1], force / params.m]

    r = solve_ivp(rhs, (t0, t_max), y0, events=event, **REFERENCE)
    return r.t[-1], r.y[0, -1], r.y[1, -1]


def pieces() -> dict:
    """The three pieces, their start states and SciPy's reference ends."""
    bc, free = ModelParams(), ModelParams(xI=1.0)
    t1, x1, v1 = _until(bc, True, IMPACT_T, [bc.xI, IMPACT_V], IMPACT_T + 0.01, TURN_START * IMPACT_V)
    t2, x2, _ = _until(bc, True, t1, [x1, v1], t1 + 0.01, 0.0)
    turn = Piece(TURN_PIECE, bc, -(v1**bc.n3), 0.0, 1.0, t1, 0.0, x1, t2 - t1, x2, v1)
    edge = BAND * free.eps
    _, xs, vs = _until(free, False, 0.0, [0.0, 0.0], 1.0, 1e9)  # the state at 1 s
    tb, xb, vb = _until(free, False, 1.0, [xs, vs], 3.0, edge, -1)
    te, xe, ve = _until(free, False, tb, [xb, vb], tb + 0.1, -edge)
    u = math.asinh(BAND)
    band = Piece(BAND_PIECE, free, -u, u, -1.0, tb, 0.0, xb, te - tb, xe, vb)
    t0f, x0f, v0f = _until(free, False, te, [xe, ve], te + 1e-3, 1e9)  # just past the band
    tf, xf, vf = _until(free, False, t0f, [x0f, v0f], t0f + 0.2, -edge, 1)
    flight = Piece(TIME_PIECE, free, t0f, tf, 0.0, 0.0, x0f, v0f, xf, vf, v0f)
    return {PIECE_NAMES[pc.kind]: pc for pc in (flight, turn, band)}


@njit(cache=True)
def _dop853_piece(p, mode, field, sgn, s0, s1, tref, a0, b0, v0, rtol, atol):
    """The core's DOP853 step over a piece (Hairer's controller): (a, b, attempts) at s1."""
    q = 1.0 / p[10]
    K = np.zeros((16, 3))
    if mode == TIME:
        t, x, v = s0, a0, b0
    else:
        t, x, v = a0, b0, v0
    d = vector_fields.deriv(p, mode, field, sgn, q, s0, tref, t, x, v)
    h = dop853.initial_step(p, mode, field, sgn, q, s0, tref, t, x, v, d[0], d[1], d[2], rtol, atol)
    s, attempts, rejected = s0, 0, False
    while s < s1 and attempts < 1_000_000:
        hs = min(h, s1 - s)
        t1, x1, v1, err = dop853.step(p, mode, field, sgn, q, s, tref, t, x, v, d[0], d[1], d[2], hs, rtol, atol, K)
        attempts += 1
        if not err <= 1.0 or not t1 > t:
            h = hs * (dop853.new_step_factor(err, False) if err < math.inf else 0.25)
            rejected = True
            continue
        h = hs * dop853.new_step_factor(err, rejected)
        rejected = False
        s = s1 if hs == s1 - s else s + hs
        t, x, v = t1, x1, v1
        d = (K[12, 0], K[12, 1], K[12, 2])
    return (x, v, attempts) if mode == TIME else (t, x, attempts)


_DOP853_MODE = {TIME_PIECE: (TIME, FREE), TURN_PIECE: (WVEL, CONTACT), BAND_PIECE: (UVEL, FREE)}


def _heyoka(piece: Piece, rtol: float):
    """heyoka's integrator of the piece's equations (in its variable, s measured from s0)."""
    import heyoka as hy

    p = piece.params
    a, b = hy.make_vars("a", "b")
    if piece.kind == TIME_PIECE:  # a = x, b = v, time from s0
        force = (
            p.m0e * OMEGA**2 * hy.sin(OMEGA * (hy.time + piece.s0))
            - p.k * a
            - p.c * b
            - p.T * b / hy.sqrt(b * b + p.eps**2)
        )
        return hy.taylor_adaptive([(a, b), (b, force / p.m)], [piece.a0, piece.b0], tol=rtol)
    if piece.kind == TURN_PIECE:  # a = tau, b = x; w = -s = |v|^n3, v = w^q
        w = -(hy.time + piece.s0)
        vel, dvel = w ** (1 / p.n3), -(1 / p.n3) * w ** (1 / p.n3 - 1)
        gap15 = (b - p.xI) ** 1.5
        contact = p.kI * (gap15 + p.b * gap15 * w)
    else:  # a = tau, b = x; u = sgn s
        u = piece.sgn * (hy.time + piece.s0)
        vel, dvel = p.eps * hy.sinh(u), piece.sgn * p.eps * hy.cosh(u)
        contact = 0.0
    force = (
        p.m0e * OMEGA**2 * hy.sin(OMEGA * (a + piece.tref))
        - p.k * b
        - p.c * vel
        - p.T * vel / hy.sqrt(vel * vel + p.eps**2)
    )
    acc = (force - contact) / p.m
    return hy.taylor_adaptive([(a, dvel / acc), (b, vel * dvel / acc)], [piece.a0, piece.b0], tol=rtol)


def _median_seconds(run, repeats: int, inner: int) -> tuple:
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(inner):
            out = run()
        times.append((time.perf_counter() - start) / inner)
    return float(np.median(times)), out


def measure_pieces(rtols=(1e-9, 1e-10, 1e-11), orders=(12, 16, 20), repeats=5, inner=200, heyoka=True) -> list[dict]:
    """One row per piece x method x rtol (atol = rtol / 100): steps, time, errors at the end."""
    rows = []
    for name, pc in pieces().items():
        p = pc.params.as_array(OMEGA)
        mode, field = _DOP853_MODE[pc.kind]
        for rtol in rtols:
            atol = rtol / 100
            runs = {
                "DOP853 (the core's step)": lambda: _dop853_piece(
                    p, mode, field, pc.sgn, pc.s0, pc.s1, pc.tref, pc.a0, pc.b0, pc.v0, rtol, atol
                )
            }
            for n in orders:
                runs[f"Taylor order {n} (numba)"] = lambda n=n: integrate_piece(
                    p, pc.kind, pc.s0, pc.s1, pc.sgn, pc.tref, pc.a0, pc.b0, n, rtol, atol
                )
            if heyoka:
                runs.update(_heyoka_run(pc, rtol))
            for method, run in runs.items():
                seconds, (a, b, steps) = _median_seconds(run, repeats, inner)
                rows.append(
                    {
                        "piece": name,
                        "method": method,
                        "rtol": rtol,
                        "steps": int(steps),
                        "us_per_piece": seconds * 1e6,
                        "ns_per_step": seconds / steps * 1e9,
                        "error_a": abs(a - pc.a_end),
                        "error_b": abs(b - pc.b_end),
                    }
                )
    return rows


def _heyoka_run(pc: Piece, rtol: float) -> dict:
    try:
        integrator = _heyoka(pc, rtol)
    except ImportError:
        return {}
    y0 = [pc.a0, pc.b0]

    def run():
        integrator.time = 0.0
        integrator.state[:] = y0
        outcome = integrator.propagate_until(pc.s1 - pc.s0)
        return integrator.state[0], integrator.state[1], outcome[3]

    return {f"heyoka order {integrator.order}": run}


# the piece measured for each of the core's variables (contact onset and exit in sqrt(h) as the turn)
MODE_PIECE = {
    "time": PIECE_NAMES[TIME_PIECE],
    "sqrth": PIECE_NAMES[TURN_PIECE],
    "wvel": PIECE_NAMES[TURN_PIECE],
    "uvel": PIECE_NAMES[BAND_PIECE],
}


def core_per_period(rtol: float, repeats: int = 3) -> dict:
    """The core on the chaotic scene (500 s): median wall time per forcing period (us) and its
    step attempts per period in each variable."""
    from impactosc.core.simulation import simulate, warm_up

    warm_up()
    periods = 500.0 * OMEGA / (2 * math.pi)
    walls = []
    for _ in range(repeats):
        r = simulate(OMEGA, 100.0, 400.0, rtol=rtol, atol=rtol / 100, record=("impacts",))
        walls.append(r.attrs["wall_time"])
    attempts = {key: r.attrs[f"n_attempts_{key}"] / periods for key in MODE_PIECE}
    return {"rtol": rtol, "us_per_period": float(np.median(walls)) / periods * 1e6, "attempts": attempts}


def projection(rows: list[dict], core: dict) -> list[dict]:
    """The core's time per period if every piece of a kind cost what the fastest numba Taylor
    order (or heyoka) takes on the measured piece, the rest (events, dense output) unchanged."""
    at = [r for r in rows if r["rtol"] == core["rtol"]]
    dop = {r["piece"]: r for r in at if r["method"].startswith("DOP853")}
    per_attempt = {m: dop[MODE_PIECE[m]]["us_per_piece"] / dop[MODE_PIECE[m]]["steps"] for m in MODE_PIECE}
    steps = sum(core["attempts"][m] * per_attempt[m] for m in MODE_PIECE)
    rest = core["us_per_period"] - steps
    out = []
    for family in ("Taylor", "heyoka"):
        best = {}
        for r in at:
            faster = r["piece"] not in best or r["us_per_piece"] < best[r["piece"]]["us_per_piece"]
            if r["method"].startswith(family) and faster:
                best[r["piece"]] = r
        if len(best) < len(dop):
            continue
        ratio = {m: best[MODE_PIECE[m]]["us_per_piece"] / dop[MODE_PIECE[m]]["us_per_piece"] for m in MODE_PIECE}
        projected = rest + sum(core["attempts"][m] * per_attempt[m] * ratio[m] for m in MODE_PIECE)
        out.append(
            {
                "method": f"{family} on every piece (fastest order per piece)"
                if family == "Taylor"
                else "heyoka's cost per piece (LLVM-compiled Taylor)",
                "rtol": core["rtol"],
                "core_us_per_period": core["us_per_period"],
                "steps_us_per_period": steps,
                "rest_us_per_period": rest,
                "projected_us_per_period": projected,
                "speedup_of_core": core["us_per_period"] / projected,
            }
        )
    return out


def taylor_through_the_band(tol: float = 1e-10, horizon: float = 5.0) -> dict:
    """heyoka's Taylor method in time through the friction bands of free flight (what the
    free-flight floor of benchmark_core does): steps per period and its error at ``horizon``
    against SciPy. Its step-size rule does not see the band's switch (width eps / |a| in time):
    with the band in time a Taylor method is fast and wrong, which is why the core integrates
    the band in asinh(v/eps)."""
    from impactosc_bench.free_flight import heyoka_free_flight

    free = ModelParams(xI=1.0)
    integrator = heyoka_free_flight(tol, free, OMEGA)
    outcome = integrator.propagate_until(horizon)
    _, x_ref, v_ref = _until(free, False, 0.0, [0.0, 0.0], horizon, 1e9)
    return {
        "tol": tol,
        "steps_per_period": outcome[3] / (horizon * OMEGA / (2 * math.pi)),
        "error_x": abs(integrator.state[0] - x_ref),
        "error_v": abs(integrator.state[1] - v_ref),
    }


def taylor_markdown(rows: list[dict], core: dict, projected: list[dict], lead_over_peer: float, band=None) -> str:
    """The pieces table and the projection, in words and numbers."""
    lines = [
        "# Taylor steps against the core's DOP853 steps, piece by piece",
        "",
        "Each piece integrated from its start to its end (atol = rtol / 100; times are medians). Errors "
        "against SciPy DOP853 at rtol 1e-13 in time: free flight error a = x (m), b = v (m/s); the turn and "
        "the band error a = t (s), b = x (m).",
        "",
        "| piece | method | rtol | steps (attempts) | us per piece | ns per step | error a | error b |",
        "|---|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['piece']} | {r['method']} | {r['rtol']:.0e} | {r['steps']} | {r['us_per_piece']:.2f} | "
        f"{r['ns_per_step']:.0f} | {r['error_a']:.1e} | {r['error_b']:.1e} |"
        for r in rows
    ]
    att = ", ".join(f"{k} {v:.1f}" for k, v in core["attempts"].items())
    lines += [
        "",
        f"The core on the chaotic scene at rtol {core['rtol']:g}: {core['us_per_period']:.1f} us per forcing period; "
        f"step attempts per period by variable: {att}.",
        "",
        "| projection | core us/period | of which steps | rest | projected us/period | core speed-up | "
        "projected lead over the fastest compiled peer |",
        "|---|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['method']} | {r['core_us_per_period']:.1f} | {r['steps_us_per_period']:.1f} | "
        f"{r['rest_us_per_period']:.1f} | {r['projected_us_per_period']:.1f} | {r['speedup_of_core']:.2f}x | "
        f"{lead_over_peer * r['speedup_of_core']:.2f}x |"
        for r in projected
    ]
    lines += ["", f"Lead over the fastest compiled peer today (benchmark_core's headline): {lead_over_peer:.2f}x."]
    if band is not None:
        lines += [
            "",
            f"A Taylor method in time through the friction bands (heyoka, tol {band['tol']:g}, free flight from "
            f"rest, as the free-flight floor): {band['steps_per_period']:.1f} steps per forcing period, and after "
            f"5 s its state is off by {band['error_x']:.1e} m in x and {band['error_v']:.1e} m/s in v (SciPy, "
            "rtol 1e-13): its step-size rule steps over the band's switch. Integrated accurately the band costs "
            "the steps of the friction-band row above, about one band per free-flight reversal.",
        ]
    return "\n".join(lines) + "\n"
