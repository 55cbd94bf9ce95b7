"""Rows of section 2.1 (Fig 4 and the grazing w): the periodic regime at w = 40.86 and 23.03 rad/s.

Why a module: the periodic group's statistics (results/<study>/stats/periodic/periodic.json,
before_grazing.json and grazing.json) answer these rows and no others.
"""

from __future__ import annotations

from impactosc.statistics import PAPER_COMBINATIONS
from impactosc_study.paper.numbers import BIFURCATION, GRAZING, PERIODIC

__all__ = ["periodic_rows"]


def periodic_rows(stats: dict, grazing: dict) -> list[dict]:
    """Rows of the paper-vs-replication table for section 2.1, Fig 4 and the grazing w.

    stats: results/<study>/stats/periodic/periodic.json merged with
    results/<study>/stats/periodic/before_grazing.json; grazing: results/<study>/stats/periodic/grazing.json. Each row says
    what counts as agreement and why.
    """
    a = stats["after_grazing"]
    im = a["impact_map"]
    sp = a["spectrum"]
    b = stats["before_grazing_branch"]
    r = stats["before_grazing_from_rest"]
    br = grazing["bracket"]
    sec = "2.1 periodic regime"
    cmd_p = "snakemake -j2 periodic_rows  (results/<study>/stats/periodic/periodic.json)"
    cmd_g = "snakemake -j2 grazing  (results/<study>/stats/periodic/grazing.json)"
    cmd_b = "snakemake -j2 before_grazing_stats"
    q = round(im["periods_in_total"])
    lo, hi = sorted((br["omega_contact"], br["omega_miss"]))
    wg = grazing["omega_g"]
    paper_ws = grazing["paper_omegas"]
    frac = sp["omega1_over_omega_fraction"]
    lines_ok = all(lab["found"] is not None for lab in sp["labels"].values()) and len(sp["labels"]) == len(
        PAPER_COMBINATIONS
    )
    rational = frac[1] > 0 and abs(sp["omega1"] - frac[0] / frac[1] * a["omega"]) <= sp["resolution"]
    rows = [
        dict(
            section=sec,
            quantity=f"impacts in {a['duration']:g} s at w = {a['omega']:g} rad/s (from rest, "
            f"after {a['transient']:g} s)",
            paper=str(PERIODIC["n_impacts"]),
            replication=str(im["n_impacts"]),
            tolerance="+-1 (4 impacts per 0.818 s: a 100 s window holds 488 or 489 depending on its phase)",
            agrees="yes" if abs(im["n_impacts"] - PERIODIC["n_impacts"]) <= 1 else "no",
            command=cmd_p,
        ),
        dict(
            section=sec,
            quantity="distinct inter-impact intervals S_j (Fig 5a)",
            paper=str(PERIODIC["n_levels"]),
            replication=f"{im['n_levels']}: " + ", ".join(f"{v:.5f}" for v in im["levels"]) + " s",
            tolerance="exact count (levels clustered at 1e-3 relative; within a level they agree to 1e-9 s)",
            agrees="yes" if im["n_levels"] == PERIODIC["n_levels"] else "no",
            command=cmd_p,
        ),
        dict(
            section=sec,
            quantity="counts of the interval levels (Fig 5b)",
            paper="equal",
            replication=", ".join(map(str, im["counts"])),
            tolerance="counts differ by at most 1 (truncated cycle)",
            agrees="yes" if im["counts_equal"] else "no",
            command=cmd_p,
        ),
        dict(
            section=sec,
            quantity="sum of the four intervals (s)",
            paper=str(PERIODIC["levels_sum"]),
            replication=f"{im['total']:.5f}",
            tolerance="+-1e-4 s (the paper's last digit; it truncates 0.81848)",
            agrees="yes" if abs(im["total"] - PERIODIC["levels_sum"]) <= 1e-4 else "no",
            command=cmd_p,
        ),
        dict(
            section=sec,
            quantity="sum of the intervals = period of the trajectory",
            paper="yes (stated)",
            replication=f"sum = {im['periods_in_total']:.9f} x 2pi/w = {q} forcing periods "
            f"({im['orbit_period']:.5f} s); Poincare period {a['poincare_period']} forcing periods",
            tolerance="within 1e-6 of a whole number of forcing periods",
            agrees="yes" if abs(im["periods_in_total"] - q) < 1e-6 and a["poincare_period"] == q else "no",
            command=cmd_p,
        ),
        dict(
            section="2 (Fig 4c)",
            quantity=f"secondary frequency w1 at w = {a['omega']:g} rad/s",
            paper="w1 < w; combinations k w +- w1 (a, b, c, d, f); read as quasi-periodic",
            replication=f"w1 = {sp['omega1']:.4f} rad/s = {sp['omega1_over_omega']:.5f} w ~ {frac[0]}/{frac[1]} w; "
            f"all 5 combinations found; the regime is periodic (period {q} x 2pi/w), not quasi-periodic",
            tolerance=f"all 5 lines matched; w1 within one spectral bin ({sp['resolution']:.4f} rad/s) of "
            f"{frac[0]}/{frac[1]} w",
            agrees=("lines yes" if lines_ok else "lines no") + ("; quasi-periodic reading no" if rational else ""),
            command=cmd_p,
        ),
        dict(
            section="2 (Fig 4a)",
            quantity=f"spectrum at w = {b['omega']:g} rad/s has only the modes k w",
            paper="yes",
            replication="yes (branch attractor)" if b["spectrum"]["harmonics_only"] else "no",
            tolerance="every line within 1.5 bins of a multiple of w (60 dB dynamic range)",
            agrees="yes" if b["spectrum"]["harmonics_only"] else "no",
            command=cmd_b,
        ),
        dict(
            section="2 (Fig 3b, 4)",
            quantity="grazing bifurcation w (decreasing w)",
            paper=f"about {GRAZING['about']:g}, between {max(paper_ws):g} and {min(paper_ws):g}",
            replication=f"{wg:.5f} (bisection bracket [{lo:.7f}, {hi:.7f}]; gap line zero "
            f"{grazing['gap_fit']['omega_zero']:.7f}) on the branch followed down from {BIFURCATION['start']}",
            tolerance=f"inside ({min(paper_ws):g}, {max(paper_ws):g}); bracket width {br['width']:.1e} rad/s",
            agrees="yes" if grazing["between_paper_omegas"] else "no",
            command=cmd_g,
        ),
        dict(
            section="2 (Fig 4a)",
            quantity=f"the attractor at w = {b['omega']:g} rad/s is just before the grazing",
            paper="yes (Fig 4a)",
            replication=f"on the decreasing branch yes: period {b['poincare_period']}, "
            f"{b['impacts_per_period']:.3f} impacts per period, near miss {b['min_gap'] * 1e6:.2f} um below xI "
            f"(used for Fig 4a); from rest no: it lands on the post-grazing orbit "
            f"({r['impact_map']['n_levels']} intervals, period {r['poincare_period']})",
            tolerance="attractor type (period and impacts per period)",
            agrees="yes on the branch" if b["poincare_period"] == 1 and b["min_gap"] is not None else "no",
            command=cmd_g,
        ),
    ]
    return rows
