"""Rows on the numerics: the step-size cap the paper needed, against what the impact checks and
the statistics-against-tolerance sweep show of ours.

Why a module: the only numerics the paper states is Mathematica's MaxStepSize; these rows answer
it from checks that time nothing (results/<study>/tables/numerics/), so that two builds give the
same table. Speeds belong to the benchmarks' report (impactosc_bench.benchmarks_report).
"""

from __future__ import annotations

import math

from impactosc_study.paper.numbers import MAX_STEP_SIZE

__all__ = ["numerics_rows"]


def numerics_rows(checks: list[dict], stats_summary: list[dict], command: str) -> list[dict]:
    """Rows for the paper-vs-replication table: the paper's only statement on numerics is
    that Mathematica needed MaxStepSize = 0.01 s (periodic) and 1e-5 s (chaotic) "to avoid
    the omissions of impacts"; ours needs no cap, which the impact checks (``checks``: the
    grazing sweep and the chattering sequences) and the statistics sweep document (``stats_summary``:
    :func:`impactosc_bench.tolerance_statistics.statistics_summary`, whose verdict allows for the
    number of tests it makes)."""

    def find(case, words):
        return [r for r in checks if r["case"] == case and all(w in r["check"] for w in words)]

    graz = find("grazing", ["classifies"])
    deep = find("grazing", ["shallowest"])
    miss = find("grazing", ["near-miss"])
    chat = find("chattering", ["minus the reference"])
    n_fail = sum(1 for r in checks if r["passed"] in (False, "no"))
    grazing = (
        f"{int(graz[0]['measured'])}/{int(graz[0]['bound'])} w through grazing classified as an independent "
        f"scan does; contacts down to {deep[0]['measured']:.1g} m and near misses down to "
        f"{miss[0]['measured']:.1g} m found"
        if graz and deep and miss
        else "grazing case not run"
    )
    chatter = f"; every impact of {len(chat)} chattering sequences found (vs SciPy DOP853 1e-13)" if chat else ""
    conv = [r for r in stats_summary if r["converged"] in (True, "yes")]
    loosest = max((r["rtol"] for r in conv), default=math.nan)
    unconv = [r["rtol"] for r in stats_summary if r["converged"] not in (True, "yes")]
    n_tests, level = int(stats_summary[0]["n_tests"]), float(stats_summary[0]["family_level"])
    # the largest z among the converged tolerances: the one a 3-sd rule per test would have flagged
    worst = max(conv, key=lambda r: r["max_abs_z"], default=None)
    chance = (
        f" (largest |z| among them {worst['max_abs_z']:.2f}, at rtol {worst['rtol']:g}: Holm-adjusted p "
        f"{worst['holm_p']:.2g})"
        if worst
        else ""
    )
    off = {r["rtol"]: r["max_abs_z"] for r in stats_summary if r["rtol"] in unconv}
    return [
        {
            "section": "2.1 (numerics)",
            "quantity": "step-size cap needed so that no impact is omitted",
            "paper": f"Mathematica MaxStepSize = {MAX_STEP_SIZE['periodic']} s (periodic), "
            f"{MAX_STEP_SIZE['chaotic']} s (chaotic)",
            "replication": f"no cap (event-split adaptive core): {grazing}{chatter}; {n_fail} of {len(checks)} impact "
            "checks failed (results/<study>/tables/numerics/impact_checks.csv)",
            "tolerance": "no impact missed or invented against independent references",
            "agrees": "n.a.",
            "command": command,
        },
        {
            "section": "2.2 (numerics)",
            "quantity": "tolerance at which the chaotic statistics converge",
            "paper": "not stated",
            "replication": (
                f"counts, windows, C_V^2 and ISI maxima consistent with an ensemble of realisations "
                f"at every core rtol up to {loosest:g}{chance}"
                + (f"; not at rtol {', '.join(f'{u:g} (|z| up to {off[u]:.1f})' for u in unconv)}" if unconv else "")
            ),
            "tolerance": (
                f"no z-score rejected by Holm's step-down over the {n_tests} two-sided normal p-values of the "
                f"z-scores against the ensemble (each statistic and window count at every rtol), family-wise "
                f"level {level:.2g} = one 3-sd test "
                "(results/<study>/tables/numerics/tolerance_statistics_summary.csv)"
            ),
            "agrees": "n.a.",
            "command": command,
        },
    ]
