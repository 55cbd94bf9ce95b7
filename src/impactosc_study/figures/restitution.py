"""The restitution laws' effective restitution of a free impact against their nominal e and v0.

Takes the rows of :func:`impactosc.dynamics.restitution.restitution_rows` and returns a
matplotlib Figure: (a) e_eff against the nominal e at one v0, the diagonal e_eff = e dashed;
(b) e_eff against v0 at one e (flat: the laws' chi scales as 1 / v0, so a free impact is
self-similar in v0).
"""

from __future__ import annotations

from matplotlib import pyplot as plt

from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["restitution_figure"]


def restitution_figure(by_e: list[dict], by_v0: list[dict]):
    """(a) the rows of one v0 over e, (b) the rows of one e over v0 (each row: law, e, v0, e_eff)."""
    apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(DOUBLE, 0.42 * DOUBLE), constrained_layout=True)
    a.plot([0, 1], [0, 1], "k--", lw=0.8, label="e_eff = e")
    laws = list(dict.fromkeys(r["law"] for r in [*by_e, *by_v0]))  # the restitution laws, in their order
    for law, color in zip(laws, (f"C{i}" for i in range(len(laws)))):
        rows = [r for r in by_e if r["law"] == law]
        a.plot([r["e"] for r in rows], [r["e_eff"] for r in rows], "o-", color=color, ms=3, label=law)
        rows = [r for r in by_v0 if r["law"] == law]
        b.semilogx([r["v0"] for r in rows], [r["e_eff"] for r in rows], "o-", color=color, ms=3, label=law)
    v0 = by_e[0]["v0"] if by_e else float("nan")
    e = by_v0[0]["e"] if by_v0 else float("nan")
    a.set(xlabel="nominal e", ylabel="effective e (free impact)", xlim=(0, 1), ylim=(0, 1))
    a.set_title(f"(a) v0 = {v0:g} m/s", loc="left")
    a.legend(fontsize="small")
    b.axhline(e, color="k", ls="--", lw=0.8)
    b.set(xlabel="impact velocity v0 (m/s)", ylabel="effective e (free impact)", ylim=(0, 1))
    b.set_title(f"(b) nominal e = {e:g}", loc="left")
    return fig
