"""The table of located bifurcation points: every special point of every continued segment,
beside the reading of the brute-force sweeps that it refines, and the period-doubling
cascade's interval ratios.

Why: a sweep reads a bifurcation as the middle of two grid points (0.02-0.025 rad/s apart);
the orbits locate it to 1e-9 rad/s (doubling) or better than 1e-7 (grazing, fold). Setting
the two side by side shows how far each reading was off, and a reading with no located point
beside it (or the reverse) shows what the sweeps cannot see.
"""

from __future__ import annotations

import numpy as np

from impactosc.dynamics.cascade import feigenbaum_ratios

__all__ = ["KIND_LABELS", "bifurcation_table", "cascade_chain", "chain_ratios", "multipliers_text"]

KIND_LABELS = {"period_doubling": "period doubling", "fold": "fold", "grazing": "grazing"}
SAME_POINT = 1e-7  # rad/s: two located points of one kind and period closer than this are one


def multipliers_text(re, im) -> str:
    """Multipliers as short text: 'a, b' (real) or 'a +- bi' (a complex pair)."""
    mu = np.asarray(re) + 1j * np.asarray(im)
    if np.any(np.abs(mu.imag) > 1e-12):
        return f"{mu[0].real:.4g} +- {abs(mu[0].imag):.4g}i (|mu| = {abs(mu[0]):.4g})"
    return ", ".join(f"{m.real:.4g}" for m in mu)


def _reading(point: dict, transitions: list[dict], sweep: str, near: float) -> dict | None:
    """The sweep's transition this point refines: the nearest of a matching kind within `near`."""

    def w_of(t):
        return float(t["grazing_omega_zero"]) if point["kind"] == "grazing" else float(t["omega"])

    def matches(t):
        if t["sweep"] != sweep:
            return False
        if point["kind"] == "grazing":
            return str(t["is_grazing"]) == "True" and t["grazing_omega_zero"] not in ("", None)
        if point["kind"] == "period_doubling":
            n = point["n_periods"]
            return t["kind"] == "period doubling" and t["detail"] in (
                f"period {n} -> {2 * n}",
                f"period {2 * n} -> {n}",
            )
        return True  # a fold shows as a jump of any kind

    cands = [t for t in transitions if matches(t) and abs(w_of(t) - point["omega"]) <= near]
    if not cands:
        return None
    t = min(cands, key=lambda t: abs(w_of(t) - point["omega"]))
    return {
        "omega": w_of(t),
        "between": sorted((float(t["omega_before"]), float(t["omega_after"]))),
        "detail": t["detail"],
    }


def bifurcation_table(segments: dict, transitions: list[dict], *, sweeps=("increasing", "decreasing"), near=0.1):
    """One row per distinct special point of the segments (dict name -> segment file's dict),
    sorted by w, with the readings of each sweep (the rows of bifurcation_transitions.csv)."""
    rows, kept = [], []
    for name, seg in segments.items():
        for p in seg["special_points"]:
            key = (p["kind"], p["n_periods"])
            if any(k == key and abs(w - p["omega"]) < SAME_POINT for k, w in kept):
                continue  # the same point reached twice (a branch that closes on itself)
            kept.append((key, p["omega"]))
            row = {
                "kind": KIND_LABELS.get(p["kind"], p["kind"]),
                "omega_rad_s": f"{p['omega']:.10f}" if p["located"] else "",
                "located": "yes" if p["located"] else f"no: {p.get('why', '')}",
                "bracket_rad_s": f"{min(p['bracket']):.6f}-{max(p['bracket']):.6f}",
                "segment": name,
                "period": p["n_periods"],
                "impacts_per_orbit": "->".join(str(i) for i in p["impacts"])
                if p["impacts"][0] != p["impacts"][1]
                else str(p["impacts"][0]),
                "multipliers_at_point": multipliers_text(p["mu_re"], p["mu_im"]) if p["located"] else "",
                "multipliers_before": multipliers_text(p["mu_before_re"], p["mu_before_im"]),
                "multipliers_after": multipliers_text(p["mu_after_re"], p["mu_after_im"]),
            }
            for sweep in sweeps:
                r = _reading(p, transitions, sweep, near)
                row[f"{sweep}_sweep_reads"] = (
                    f"{r['omega']:.4f} ({r['detail']}; grid {r['between'][0]:.3f}-{r['between'][1]:.3f})" if r else ""
                )
                row[f"{sweep}_minus_located"] = f"{r['omega'] - p['omega']:+.4f}" if r and p["located"] else ""
            rows.append((p["omega"], row))
    return [row for _, row in sorted(rows, key=lambda t: t[0])]


def cascade_chain(segments: dict) -> list[dict]:
    """The longest chain of located period doublings N -> 2N -> 4N ..., each on the segment
    switched at the one before (config `doubling_of`): the cascade the orbits follow."""

    def doublings(name):
        return [p for p in segments[name]["special_points"] if p["kind"] == "period_doubling" and p["located"]]

    def child_doubling(name, pd):
        for child, seg in segments.items():
            parent = seg.get("spec", {}).get("doubling_of")
            if parent and parent["segment"] == name and doublings(name):
                born_at = min(doublings(name), key=lambda p: abs(p["omega"] - parent["near"]))
                if born_at is pd and doublings(child):
                    return child, min(doublings(child), key=lambda p: abs(p["omega"] - pd["omega"]))
        return None

    best = []
    for name in segments:
        for pd in doublings(name):
            chain, at = [pd], (name, pd)
            while (at := child_doubling(*at)) is not None:
                chain.append(at[1])
            best = max(best, chain, key=len)
    return best


def chain_ratios(chain: list[dict]) -> list[float]:
    """Ratios of successive intervals of a cascade chain (Feigenbaum's delta in the limit)."""
    return feigenbaum_ratios([p["omega"] for p in chain]) if len(chain) >= 3 else []
