"""Rows of the experimental panels (Figs 8b, 9b, 10 lower), the paper's remark on sensor noise
and the obstacle position estimated from a record.

Why a module: these rows judge a measured record (or, until there is one, the labelled
surrogate, when they say n.a.) with the same analysis as the model.
"""

from __future__ import annotations

import numpy as np

from impactosc_study.paper.numbers import MEASURED

__all__ = ["measured_rows"]


def measured_rows(
    second: dict, model: dict, noise_rows: list[dict], *, is_surrogate: bool, command: str, dynamic: dict | None = None
):
    """Rows of the paper-vs-replication table for the experimental panels (Figs 8b, 9b, 10).

    ``second`` and ``model`` are :func:`impactosc.statistics.train_analysis.analyse_train` results of the
    record's train and of the model's.  While the record is the surrogate, the paper's
    experimental numbers cannot be checked: the rows say so (agrees = n.a.) and report what
    the record path gives.
    """
    label = second["train"]["label"]
    src = f"{label} (not the rig)" if is_surrogate else label
    verdict = (lambda ok: "n.a.") if is_surrogate else (lambda ok: "yes" if ok else "no")
    cv, cvm = second["variability"]["cv2_paper"], model["variability"]["cv2_paper"]
    isi = second["isi_density"]
    mx = np.asarray(isi["maxima"], dtype=float)
    rel = np.asarray(isi["maxima_relative_height"], dtype=float)
    acf = second["acf"]
    rows = [
        {
            "quantity": "Fig 8b: C_V^2 (var/mean of the ISIs, s) of the measured train, large i",
            "paper": f"about {MEASURED['cv2_paper']:g}, a little above the model's",
            "replication": f"{src}: {cv:.4f} s (model {cvm:.4f} s), {second['train']['n_impacts']} impacts",
            "tolerance": "[0.025, 0.035) s and above the model's",
            "agrees": verdict(0.025 <= cv < 0.035 and cv > cvm),
        },
        {
            "quantity": "Fig 9b: ISI density of the measured train",
            "paper": "substantial maximum for long intervals, weakly expressed extremum for short ones",
            "replication": f"{src}: {isi['n_modes']} maxima at "
            + ", ".join(f"{m:.3f}" for m in mx)
            + " s, relative heights "
            + ", ".join(f"{r:.2f}" for r in rel),
            "tolerance": "long-interval maximum the highest; short-interval maximum lower",
            "agrees": verdict(mx.size >= 2 and rel[-1] == 1.0),
        },
        {
            "quantity": "Fig 10 lower: ACF-spectrum extrema of the measured train",
            "paper": "two weakly prevailing extrema (noise)",
            "replication": f"{src}: {acf['n_significant']} peak(s) above the shuffled-surrogate level, at f = "
            + ", ".join(f"{f:.3f}" for f in acf["peak_frequency"]),
            "tolerance": "two extrema",
            "agrees": verdict(len(acf["peak_frequency"]) >= 2),
        },
    ]
    loc, locm = second.get("local_variability"), model.get("local_variability")
    if loc and locm:
        rows.append(
            {
                "quantity": "beyond the paper: local variability of the measured ISIs (CV2, LV, LvR), beside the model's",
                "paper": "not computed",
                "replication": f"{src}: CV2 {loc['holt_cv2']:.3f}, LV {loc['lv']:.3f}, LvR {loc['lvr']:.3f}, "
                f"r(1) {loc['serial_correlation'][0]:+.3f} (model {locm['holt_cv2']:.3f}, {locm['lv']:.3f}, "
                f"{locm['lvr']:.3f}, {locm['serial_correlation'][0]:+.3f}); local measures stay valid when a rig's "
                "rate drifts, where C_V^2 does not",
                "tolerance": "n.a. (beyond the paper; impactosc stats RIG.h5 --against MODEL.h5 adds the distances)",
                "agrees": "n.a.",
            }
        )
    rates = sorted({r["rate_hz"] for r in noise_rows})
    if rates:
        rate = min(rates, key=lambda r: abs(r - 2000.0))  # a data-acquisition card's rate
        at = [r for r in noise_rows if r["rate_hz"] == rate]
        exact = next(r for r in at if r["method"] == "exact events")
        parts = []
        for r in at:
            if r["method"] != "hysteresis" or "isi_n_modes" not in r:
                continue
            parts.append(
                f"{1e6 * r['noise_m']:g} um: {r['isi_n_modes']} max., C_V^2 {r['cv2_paper']:.4f} s, "
                f"{r['missed']} missed/{r['extra']} extra"
            )
        naive = [r for r in at if r["method"] == "naive threshold" and "cv2_paper" in r]
        worst = max(naive, key=lambda r: r["noise_m"]) if naive else None
        hyst = [r for r in at if r["method"] == "hysteresis" and "isi_n_modes" in r]
        unimodal = [r for r in hyst if r["isi_n_modes"] < 2]
        if unimodal:
            first = min(unimodal, key=lambda r: r["noise_m"])
            finding = (
                f"Unimodal from {1e6 * first['noise_m']:g} um on, where noise hides the shallow contacts "
                f"({first['missed']} missed)"
            )
        else:
            top = max((r["noise_m"] for r in hyst), default=0.0)
            finding = f"Bimodal at every level up to {1e6 * top:g} um: noise on x hides shallow contacts, it does not merge the maxima"
        rows.append(
            {
                "quantity": "sensor noise turns the bimodal ISI distribution unimodal (paper, after Sauer 1995)",
                "paper": "stated, not quantified",
                "replication": f"model + white noise on x at {rate:g} Hz, hysteresis extraction (exact events: "
                f"{exact['isi_n_modes']} max., C_V^2 {exact['cv2_paper']:.4f} s): "
                + "; ".join(parts)
                + (
                    f". Naive threshold crossing at {1e6 * worst['noise_m']:g} um: {worst['extra']} false impacts, "
                    f"C_V^2 {worst['cv2_paper']:.4f} s"
                    if worst
                    else ""
                )
                + f". {finding}; results/<study>/tables/measured/measured_noise_study.csv. "
                + dynamic_noise_finding(dynamic),
                "tolerance": "n.a. (beyond the paper: measurement noise on x, and noise in the dynamics)",
                "agrees": "n.a.",
            }
        )
        obstacle = _obstacle_row(at, rate)
        if obstacle:
            rows.append(obstacle)
    for r in rows:
        r.update(section="2.2 experimental panels", command=command)
    return rows


def _obstacle_row(at: list[dict], rate: float) -> dict | None:
    """Beyond the paper: the obstacle position estimated from the noise study's records (no xI
    given), error and stated sigma per noise level; None when the study did not estimate it."""
    est = [r for r in at if r["method"] == "hysteresis" and np.isfinite(r.get("x_impact_err_m", np.nan))]
    if not est:
        return None
    parts = [
        f"{1e6 * r['noise_m']:g} um: {1e6 * r['x_impact_err_m']:+.2f} um (sigma {1e6 * r['x_impact_sigma_m']:.2f})"
        for r in est
    ]
    goal = [r for r in est if 5e-6 <= r["noise_m"] <= 1e-5]
    met = all(abs(r["x_impact_err_m"]) < 3e-6 and abs(r["x_impact_err_m"]) < 3 * r["x_impact_sigma_m"] for r in goal)
    return {
        "quantity": "beyond the paper: obstacle position xI from a record that does not give it (contact-law fit)",
        "paper": "xI set on the rig, not estimated",
        "replication": f"surrogate at {rate:g} Hz, first 60 s, error (stated sigma): "
        + "; ".join(parts)
        + (f". At 5-10 um noise within 3 um and 3 sigma: {'yes' if met else 'no'}" if goal else "")
        + ". Bias and coverage over 30 draws per level: snakemake -j2 measured_x_impact_coverage",
        "tolerance": "|error| < 3 um at 5-10 um noise, covered by the stated sigma",
        "agrees": "n.a.",
    }


def dynamic_noise_finding(summary: dict | None) -> str:
    """What the dynamic-noise study (impactosc_study.dynamic_noise.summary) found about the ISI maxima,
    as a sentence of the noise row; where the beyond tier has not been built, how to build it."""
    if not summary:
        return "Noise in the dynamics: not built with the paper (snakemake -j2 dynamic_noise_study, beyond tier)"
    names = {"motor": "motor speed jitter", "force": "random force on the cart"}
    parts = []
    for name, s in summary.items():
        where = (
            f"the ISI maxima merge at {s['merge_rms']:g} {s['unit']} rms"
            if s["merge_rms"] is not None
            else f"the ISI maxima stay two up to {s['largest_rms']:g} {s['unit']} rms (the largest tried)"
        )
        at = s["at_largest"]
        cv2, lv, r1 = at["cv2_paper"], at["lv"], at["serial_correlation_1"]
        first = min(((v, k) for k, v in s["moved_10_percent_at"].items() if v is not None), default=None)
        moved = f"; first to move by 10 %: {first[1]} at {first[0]:g} {s['unit']}" if first else ""
        parts.append(
            f"{names.get(name, name)} (tau {s['tau_s']:g} s): {where}{moved}; at {s['largest_rms']:g} {s['unit']} "
            f"C_V^2 {cv2[0]:.4f} -> {cv2[1]:.4f} s, LV {lv[0]:.3f} -> {lv[1]:.3f}, r(1) {r1[0]:+.3f} -> {r1[1]:+.3f}"
        )
    return (
        "Noise in the dynamics: " + "; ".join(parts) + " (results/<study>/tables/dynamic_noise/dynamic_noise_study.csv)"
    )
