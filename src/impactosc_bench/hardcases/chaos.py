"""Hard cases on the chaotic scene (w = 40.86 rad/s): regularisation (eps down to 1e-9 m/s,
a stiffer contact) and a long run (10^4 s).

Why a module: a chaotic trajectory cannot be compared point by point, so both cases judge
the impact train's statistics (:func:`impactosc_bench.tolerance_statistics.train_statistics`
against an ensemble of realisations), the contact's scaling law, memory and speed.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from impactosc.core.simulation import simulate, warm_up
from impactosc.model.parameters import ModelParams
from impactosc.statistics.multiple_testing import largest_z_bound
from impactosc_bench.hardcases.checks import row
from impactosc_bench.tolerance_statistics import STAT_KEYS, train_statistics, window_zscores, zscores

# ======================================================================== regularisation


def _chaos_stats(params, omega, transient, duration, x0=0.0, rtol=1e-10, atol=1e-12):
    t0 = time.perf_counter()
    res = simulate(omega, transient, duration, x0=x0, params=params, rtol=rtol, atol=atol, record=("impacts",))
    wall = time.perf_counter() - t0
    return train_statistics(res.events["impacts"]["t"], transient, transient + duration, omega), wall, res.attrs


def _z(stats, ens):
    """Largest |z| over the statistics against the ensemble, which statistic it is, and how many
    z-scores it is the largest of (each window count is one)."""
    zs = {k: abs(v) for k, v in zscores(stats, ens).items()}
    worst = max(zs, key=zs.get)
    return zs[worst], worst, len(STAT_KEYS) + len(window_zscores(stats, ens))


def regularisation_case(
    eps_values=(1e-7, 1e-8, 1e-9),
    kI_factor=100.0,
    ensemble_x0=(1e-4, -1e-4, 2e-4, -2e-4, 5e-4, -5e-4, 1e-3, -1e-3),
    omega=40.86,
    transient=100.0,
    duration=400.0,
    approach_speeds=(0.02, 0.1, 0.5, 1.5),
    log=print,
) -> list[dict]:
    """Stiffer regularisation and a stiffer contact.

    eps: at the chaotic scene the velocities are ~0.1 m/s and the cart only rarely sticks,
    so eps from 1e-6 down to 1e-9 m/s may not move the statistics (impact count, 5 window
    counts, C_V^2, ISI density maxima) beyond an ensemble of eps = 1e-6 realisations: the worst
    of the 10 z-scores within Holm's (Bonferroni's) bound for 10 tests at the level of one 3-sd
    test (:func:`impactosc.statistics.multiple_testing.largest_z_bound`). Each z is taken against
    the ensemble's own mean and sample sd, so the bound is the prediction interval's (Student's t,
    7.1 for 8 realisations; the normal 3.6 rejected 1 in 6 realisations of eps = 1e-6 itself,
    where the ISI density's first maximum jumps between two close peaks). The work (RHS
    evaluations) may not grow (bound: 2 x the eps = 1e-6 run).

    kI x f: both contact terms carry h^1.5, so at a fixed impact velocity the contact alone
    is invariant under h -> f^(-2/5) h, t -> f^(-2/5) t: the deepest penetration scales by
    exactly f^(-2/5) (0.158 for f = 100), the restitution is unchanged. The forces the
    contact scaling ignores (forcing, spring, friction; F_o) bound the deviation at first
    order: |ratio / f^(-2/5) - 1| <= F_o / F_peak. The chaotic statistics do change (the
    contact time shrinks, the attractor moves): reported, not bounded. The work (RHS
    evaluations) may not grow beyond 2 x kI's: the scaling leaves the steps per contact
    unchanged. Wall times are reported in the row's detail, never bounded here.
    """
    base = ModelParams()
    rows = []
    ens = [_chaos_stats(base, omega, transient, duration, x0=x0)[0] for x0 in ensemble_x0]
    ref, wall0, attrs0 = _chaos_stats(base, omega, transient, duration)
    spread = np.std([e["n_impacts"] for e in ens], ddof=1)
    log(f"eps 1e-6: {ref['n_impacts']} impacts, wall {wall0:.3f} s; ensemble of {len(ens)}: n std {spread:.1f}")
    for eps in eps_values:
        rows += _eps_rows(dataclasses.replace(base, eps=eps), omega, transient, duration, ens, wall0, attrs0, log)
    # stiffer contact: single impacts from the same approach
    stiff = dataclasses.replace(base, kI=base.kI * kI_factor)
    rows += _scaling_rows(base, stiff, kI_factor, omega, approach_speeds)
    st, wall, attrs = _chaos_stats(stiff, omega, transient, duration)
    z, worst, _ = _z(st, ens)
    log(f"kI x {kI_factor:g}: {st['n_impacts']} impacts, worst z {z:.1f} ({worst}), wall {wall:.3f} s")
    rows.append(
        row(
            "regularisation",
            f"kI x {kI_factor:g}: chaotic statistics, worst |z| against the kI ensemble "
            "(the attractor itself changes: reported, not bounded)",
            z,
            "n.a.",
            "std",
            info=True,
            detail=f"{st['n_impacts']} impacts (kI: {ref['n_impacts']}), C_V^2 {st['cv2_paper']:.4f} s "
            f"({ref['cv2_paper']:.4f}), ISI maxima {st['isi_first_maximum']:.4f}/{st['isi_last_maximum']:.4f} s "
            f"({ref['isi_first_maximum']:.4f}/{ref['isi_last_maximum']:.4f}); worst: {worst}",
        )
    )
    # Work, not wall time (a timed bound failed on a loaded machine; speed goals live in the
    # benchmarks). Bound 2: the contact is self-similar under kI -> f kI (h -> f^(-2/5) h,
    # t -> f^(-2/5) t, v unchanged), so an adaptive step needs as many steps per contact as
    # before and the free flight is unchanged; the work moves only with the impact count of
    # the moved attractor (0.93 x kI's for f = 100; realisations of one attractor differ by
    # ~1 %). The contact and friction-band pieces take ~80 % of the steps, so a ratio above 2
    # means the work per contact grew more than ~2.2-fold with the stiffness: the contact
    # scaling is no longer resolved at constant cost.
    rhs, rhs0 = attrs["n_rhs"], attrs0["n_rhs"]
    rows.append(
        row(
            "regularisation",
            f"kI x {kI_factor:g}: RHS evaluations of the 500 s chaotic scene over kI's "
            "(bound: same work per contact, scaling law)",
            rhs / rhs0,
            2.0,
            "ratio",
            detail=f"{rhs} against {rhs0} RHS evaluations, {attrs['n_steps']} against {attrs0['n_steps']} "
            f"steps; wall {wall:.3f} s against {wall0:.3f} s (ratio {wall / wall0:.2f}, information only: "
            "timings are judged in the benchmarks)",
        )
    )
    return rows


def _eps_rows(params, omega, transient, duration, ens, wall0, attrs0, log) -> list[dict]:
    """The chaotic statistics at a smaller regularisation eps (`params`) against the ensemble
    `ens` of eps = 1e-6 realisations, and the work against eps = 1e-6's run (`attrs0`)."""
    rows = []
    eps = params.eps
    st, wall, attrs = _chaos_stats(params, omega, transient, duration)
    z, worst, n_tests = _z(st, ens)
    log(
        f"eps {eps:g}: {st['n_impacts']} impacts, C_V^2 {st['cv2_paper']:.4f} s, worst z {z:.2f} ({worst}), "
        f"wall {wall:.3f} s"
    )
    rows.append(
        row(
            "regularisation",
            f"eps {eps:g}: chaotic statistics, worst |z| of {n_tests} against {len(ens)} eps = 1e-6 "
            "realisations (counts, windows, C_V^2, ISI maxima); bound: Holm over the "
            f"{n_tests} at the level of one 3-sd test, each z against {len(ens)} references (Student's t)",
            z,
            largest_z_bound(n_tests, reference_size=len(ens)),
            "std",
            detail=f"{st['n_impacts']} impacts, windows {st['window_counts']}, C_V^2 "
            f"{st['cv2_paper']:.4f} s, maxima {st['isi_first_maximum']:.4f}/{st['isi_last_maximum']:.4f} s; "
            f"worst: {worst}; {attrs['n_stick']} sticks",
        )
    )
    # Work, not wall time (as for kI below). Bound 2: the friction band is crossed in
    # asinh(v/eps) and sticking is handed to the implicit phase, so the work should not
    # depend on eps (measured 1.02-1.10 x eps = 1e-6's for eps = 1e-7..1e-9, realisations
    # differ by ~1 %); explicit steps through a stick, where the friction law's stiffness
    # is ~T/(m eps), would need steps per stick growing as 1/eps.
    rhs = attrs["n_rhs"]
    rows.append(
        row(
            "regularisation",
            f"eps {eps:g}: RHS evaluations of the 500 s chaotic scene over eps = 1e-6's",
            rhs / attrs0["n_rhs"],
            2.0,
            "ratio",
            detail=f"{rhs} against {attrs0['n_rhs']} RHS evaluations, {attrs['n_steps']} against "
            f"{attrs0['n_steps']} steps; wall {wall:.3f} s against {wall0:.3f} s (ratio {wall / wall0:.2f}, "
            "information only: timings are judged in the benchmarks)",
        )
    )
    return rows


def _scaling_rows(base, stiff, kI_factor, omega, approach_speeds) -> list[dict]:
    """Single impacts from the same approach with the contact stiffened by `kI_factor`: the
    deepest penetration against the contact's scaling law f^(-2/5), one row per approach speed."""
    expected = kI_factor**-0.4
    rows = []
    for V in approach_speeds:
        h = []
        for q in (base, stiff):
            r = simulate(omega, 0.0, 0.02, x0=base.xI - 1e-6, v0=V, params=q, record=("penetrations",))
            h.append(float(r.events["penetrations"]["h"][0]))
        f_peak = base.kI * h[0] ** base.n1
        f_other = base.m0e * omega**2 + base.k * abs(base.xI) + base.c * V + base.T
        dev = abs(h[1] / h[0] / expected - 1)
        rows.append(
            row(
                "regularisation",
                f"kI x {kI_factor:g}, impact at {V:g} m/s: |H ratio / {kI_factor:g}^(-2/5) - 1| "
                "(bound: other forces / peak contact force)",
                dev,
                f_other / f_peak,
                "1",
                detail=f"H = {h[0]:.4g} m -> {h[1]:.4g} m, ratio {h[1] / h[0]:.5f} (scaling {expected:.5f})",
            )
        )
    return rows


# ============================================================================== long run


def _rss_bytes() -> float:
    """Resident memory of this process (Linux /proc; nan elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * 4096.0
    except OSError:
        return math.nan


def long_run_case(
    duration=1e4, omega=40.86, block=1000.0, chunk_steps=200_000, speed_bound=2.0, log=print
) -> list[dict]:
    """10^4 s of the chaotic scene: memory may grow only by the stored events, the impact
    rate may not drift and the speed may not degrade.

    * memory: resident size after the run minus after the first chunk, against twice the
      bytes of the event array (it grows by doubling) plus 8 MB for the allocator;
    * rate: impacts per `block` s; the least-squares trend over the run, in units of its
      standard error, must stay within 3 (no drift);
    * speed, simulated seconds per second of this process's CPU time, first progress
      interval over the last: <= `speed_bound` (None: reported, not bounded). CPU time, not
      wall time, because a process waiting for a busy core accrues none: the ratio measures
      the core, not its neighbours.
    """
    if not duration >= 4 * block > 0:
        raise ValueError(
            f"hard_cases.long_run: duration ({duration:g} s) must hold at least 4 blocks of "
            f"{block:g} s (the first is the transient; a trend and its standard error need 3 more)"
        )
    warm_up()
    marks = []
    t0 = time.process_time()

    def progress(t, t_end, n_imp):
        marks.append((t, n_imp, _rss_bytes(), time.process_time() - t0))

    res = simulate(omega, 0.0, duration, record=("impacts",), chunk_steps=chunk_steps, progress=progress)
    t = res.events["impacts"]["t"]
    edges = np.arange(0.0, duration + block / 2, block)
    counts = np.histogram(t, bins=edges)[0].astype(float)[1:]  # the first block holds the transient
    k = np.arange(counts.size, dtype=float)
    slope, icpt = np.polyfit(k, counts, 1)
    resid = counts - (slope * k + icpt)
    se = math.sqrt(resid @ resid / max(counts.size - 2, 1) / ((k - k.mean()) @ (k - k.mean())))
    event_bytes = 2 * 4 * 8 * t.size
    growth = marks[-1][2] - marks[0][2]
    speeds = [(marks[j][0] - marks[j - 1][0]) / (marks[j][3] - marks[j - 1][3]) for j in range(1, len(marks))]
    slowdown = speeds[0] / speeds[-1] if len(speeds) >= 2 else 1.0
    log(
        f"long run {duration:g} s: {t.size} impacts, blocks {counts.astype(int).tolist()}, trend {slope:+.2f} "
        f"+- {se:.2f} per block, RSS growth {growth / 1e6:.1f} MB (events {event_bytes / 1e6:.1f} MB), "
        f"{len(marks)} chunks, wall {res.attrs['wall_time']:.2f} s"
    )
    return [
        row(
            "long run",
            f"{duration:g} s chaos: resident-memory growth after the first chunk (bound: 2 x 32 B per "
            "stored event + 8 MB)",
            growth,
            event_bytes + 8e6,
            "B",
            detail=f"{t.size} impacts; {len(marks)} chunks of {chunk_steps} steps; wall {res.attrs['wall_time']:.2f} s",
        ),
        row(
            "long run",
            f"impact-rate trend per {block:g} s block, in standard errors",
            abs(slope) / se if se > 0 else 0.0,
            3.0,
            "std",
            detail=f"counts per block {counts.astype(int).tolist()}, trend {slope:+.2f} +- {se:.2f}",
        ),
        row(
            "long run",
            "speed (simulated s per CPU s), first chunk over last",
            slowdown,
            speed_bound,
            "ratio",
            detail=f"{speeds[0]:.0f} and {speeds[-1]:.0f} simulated s per CPU s" if speeds else "",
            info=speed_bound is None,
        ),
    ]
