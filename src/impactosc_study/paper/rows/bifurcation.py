"""Rows of Fig 3b: the reverse period doublings and the grazing on the decreasing sweep, read
from the bifurcation diagram (:func:`bifurcation_rows`) and located on the continued orbits
(:func:`orbit_rows`).

Why together: both builders judge the same two statements of the paper against the same
bracket, from two independent routes to the same numbers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from impactosc_study.paper.numbers import BIFURCATION, GRAZING
from impactosc_study.paper.table import agreement

if TYPE_CHECKING:  # annotations only
    from impactosc.dynamics.diagram import SweepReading, Transition

__all__ = ["bifurcation_rows", "orbit_rows"]


# the paper's two grazing w (Fig 4a/4b), as a bracket
PAPER_GRAZING_BRACKET = tuple(sorted(GRAZING["omegas"]))


def _fmt_bracket(t: Transition) -> str:
    lo, hi = sorted((t.omega_before, t.omega_after))
    return f"{t.omega:.2f} rad/s (between {lo:.3f} and {hi:.3f})"


def bifurcation_rows(
    decreasing: SweepReading,
    command: str,
    start: float = BIFURCATION["start"],
    near_fraction: float = 0.10,
    grazing_about: float = GRAZING["about"],
    grazing_tol: float = 0.5,
    paper_bracket=PAPER_GRAZING_BRACKET,
    reference_grazing: dict | None = None,
) -> list[dict]:
    """Rows of the paper-vs-replication table that the Fig 3b sweep answers.

    The paper states: reverse period doublings "close to the starting w = 40.86" and extra
    ISI branches (grazing) "at about w = 23"; Fig 4 puts the grazing between 23.05 and 23.03.
    reference_grazing: the grazing bisection of the periodic group (results/<study>/stats/periodic/grazing.json), if any.
    """
    rows = []
    pds = [t for t in decreasing.transitions if t.kind == "period doubling"]
    lower = start * (1 - near_fraction)
    if pds:
        rep = "; ".join(f"{t.detail} at {_fmt_bracket(t)}" for t in pds if t.omega >= lower)
        chaos = [t for t in decreasing.transitions if t.kind == "non-periodic boundary" and t.omega >= lower]
        if chaos:
            rep += f"; non-periodic (with periodic windows) above {min(chaos, key=lambda t: t.omega).omega:.2f} rad/s"
        agrees = "yes" if any(t.omega >= lower for t in pds) else "no"
    else:
        rep, agrees = "no period doubling detected", "no"
    rows.append(
        {
            "section": "Fig 3b",
            "quantity": f"reverse period doublings on decreasing w from {start}",
            "paper": f"close to the starting w = {start} rad/s (no value given)",
            "replication": rep,
            "tolerance": f"a period-doubling cascade within {near_fraction:.0%} below {start} "
            f"(w >= {lower:.2f} rad/s); the paper states no number",
            "agrees": agrees,
            "command": command,
        }
    )
    graz = list(decreasing.grazings)
    if graz:
        g = min(graz, key=lambda g: abs(g.omega_zero - grazing_about))
        lo, hi = g.bracket
        rep = (
            f"grazing at {g.omega_zero:.3f} rad/s (zero of the near-miss gap line), between grid points "
            f"{lo:.3f} and {hi:.3f}; {g.transition.detail}"
        )
        ok_about = abs(g.omega_zero - grazing_about) <= grazing_tol
        rows.append(
            {
                "section": "Fig 3b",
                "quantity": "additional ISI branches below the main curve (grazing)",
                "paper": f"at about w = {grazing_about:g} rad/s",
                "replication": rep,
                "tolerance": f"+-{grazing_tol} rad/s (the paper rounds to 'about {grazing_about:g}')",
                "agrees": "yes" if ok_about else "no",
                "command": command,
            }
        )
        plo, phi = paper_bracket
        inside = plo <= g.omega_zero <= phi
        ref = ""
        if reference_grazing:
            ref = (
                f"; grazing group's bisection: {reference_grazing['omega_g']:.4f} rad/s, "
                f"difference {g.omega_zero - reference_grazing['omega_g']:+.4f}"
            )
        step = decreasing.table.step
        rows.append(
            {
                "section": "Fig 3b / Fig 4",
                "quantity": "grazing w on the decreasing sweep",
                "paper": f"between {phi} (before) and {plo} (after) rad/s",
                "replication": f"{g.omega_zero:.4f} rad/s{ref}",
                "tolerance": f"inside [{plo}, {phi}] (sweep step {step:.3f} rad/s; the gap line "
                f"interpolates between grid points)",
                "agrees": "yes" if inside else "no",
                "command": command,
            }
        )
    else:
        rows.append(
            {
                "section": "Fig 3b",
                "quantity": "additional ISI branches below the main curve (grazing)",
                "paper": f"at about w = {grazing_about:g} rad/s",
                "replication": "no grazing detected",
                "tolerance": f"+-{grazing_tol} rad/s",
                "agrees": "no",
                "command": command,
            }
        )
    return rows


def orbit_rows(
    chain: list[dict], ratios: list[float], grazings: list[dict], command: str,
    start: float = BIFURCATION["start"], near_fraction: float = 0.10, paper_bracket=PAPER_GRAZING_BRACKET,
) -> list[dict]:  # fmt: skip
    """The Fig 3b rows again, with the values the continued orbits give: the doubling cascade
    (`chain`, located period doublings N -> 2N -> ..., and the `ratios` of its intervals) and
    the grazing of the period-1 orbit (`grazings`: located grazing points of period 1)."""
    lower = start * (1 - near_fraction)
    if chain:
        rep = "; ".join(f"{2 * p['n_periods']} -> {p['n_periods']} at {p['omega']:.7f}" for p in chain) + " rad/s"
        if ratios:
            rep += "; ratios of successive intervals " + ", ".join(f"{r:.2f}" for r in ratios) + " (Feigenbaum 4.669)"
        agrees = agreement(all(lower <= p["omega"] <= start for p in chain))
    else:
        rep, agrees = "no period doubling located", "no"
    rows = [
        {
            "section": "Fig 3b (orbits)",
            "quantity": f"reverse period doublings below {start}, located on the continued orbits",
            "paper": f"close to the starting w = {start} rad/s (no value given)",
            "replication": rep + " (each bisected to 1e-9 rad/s on det(M + I))",
            "tolerance": f"the cascade within {near_fraction:.0%} below {start} (w >= {lower:.2f} rad/s)",
            "agrees": agrees,
            "command": command,
        }
    ]
    plo, phi = paper_bracket
    near = [g for g in grazings if plo - 1 <= g["omega"] <= phi + 1]
    if near:
        g = min(near, key=lambda g: abs(g["omega"] - 0.5 * (plo + phi)))
        before, after = g["mu_before"], g["mu_after"]
        rep = (
            f"{g['omega']:.7f} rad/s, where the period-1 orbit's smallest near-miss gap reaches zero; "
            f"past it the orbit has {max(g['impacts'])} impacts per period and its multipliers jump from "
            f"{before} to {after}"
        )
        agrees = agreement(plo <= g["omega"] <= phi)
    else:
        rep, agrees = "no grazing of the period-1 orbit located", "no"
    rows.append(
        {
            "section": "Fig 3b / Fig 4 (orbits)",
            "quantity": "grazing w, located on the continued period-1 orbit",
            "paper": f"between {phi} (before) and {plo} (after) rad/s",
            "replication": rep,
            "tolerance": f"inside [{plo}, {phi}]",
            "agrees": agrees,
            "command": command,
        }
    )
    return rows
