"""The row every hard-case check returns: one module so that each case module and the
driver (:func:`impactosc_bench.hardcases.run_all`) build the same table."""

from __future__ import annotations


def row(case, check, measured, bound, unit, passed=None, detail="", info=False):
    """One table row; `passed` defaults to measured <= bound. An `info` row reports a
    measured figure that no bound applies to (passed: "n.a.")."""
    measured = float(measured)
    if info:
        return {
            "case": case,
            "check": check,
            "measured": measured,
            "bound": "n.a.",
            "unit": unit,
            "passed": "n.a.",
            "detail": detail,
        }
    if passed is None:
        passed = bool(measured <= bound)
    return {
        "case": case,
        "check": check,
        "measured": measured,
        "bound": bound,
        "unit": unit,
        "passed": bool(passed),
        "detail": detail,
    }
