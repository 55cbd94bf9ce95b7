"""Noise study: how sampling rate, sensor noise and sensor imperfections change the impact
train extracted from a record, scored against the surrogate's exact events.

Why a module of its own: the surrogate (:mod:`impactosc.records.surrogate`) makes records;
this scores what extraction (:mod:`impactosc.records.extract`) recovers from them -- missed and
extra impacts, timing error against the stated sigma and the Cramer-Rao bound, penetration
error, the obstacle estimate, and the train's statistics (C_V^2, ISI modes, ACF peaks).

The study is one function (:func:`noise_study`). A workflow runs it as parallel jobs, one per
sampling rate (each rate's noise draws come from a generator of its own, so the study at one rate
gives that rate's rows of the whole study) and one for the sensor-realism rows
(:func:`realism_rows`), and concatenates them in the order of the rates.
"""

from __future__ import annotations

import numpy as np

from impactosc.core.simulation import Window, simulate
from impactosc.records.extract import ExtractOptions, estimate_noise, estimate_x_impact, extract_events
from impactosc.records.impact_times import crossing_time_crb
from impactosc.records.record import Record
from impactosc.records.surrogate import (
    REALISM_FIELDS,
    SurrogateOptions,
    mismatched_params,
    sensor_samples,
    surrogate_meta,
    surrogate_record,
)
from impactosc.records.surrogate_truth import depths_at_impacts
from impactosc.statistics.impact_train import ImpactTrain
from impactosc.statistics.train_analysis import analyse_train

__all__ = [
    "TABLE_COLUMNS",
    "match_impacts",
    "noise_study",
    "realism_rows",
]

# Columns of the study's table (the rows also carry the ISI kernel densities, kept for the figure)
TABLE_COLUMNS = [
    "rate_hz",
    "noise_m",
    "method",
    "n_true",
    "n_found",
    "missed",
    "extra",
    "timing_rms_s",
    "timing_bias_s",
    "timing_max_z",
    "frac_beyond_5sigma",
    "sigma_t_median_s",
    "timing_err_median_s",
    "timing_crb_median_s",
    "timing_crb_rms_s",
    "timing_crb_ratio",
    "timing_within_2sigma",
    "timing_rms_z",
    "penetration_bias_m",
    "penetration_err_median_m",
    "x_impact_err_m",
    "x_impact_sigma_m",
    "sensor_delay_s",
    "noise_estimate_m",
    "cv2_paper",
    "cv2",
    "isi_n_modes",
    "isi_maxima",
    "isi_valley_ratio",
    "acf_n_significant",
    "note",
    "x_impact_note",
]


def match_impacts(true_t, found_t):
    """Nearest-neighbour one-to-one matching of found to true impact times (both sorted).

    A found time is matched to its nearest true one if it lies within half the gap to that
    one's neighbours; a true time claimed twice keeps its first claimant.  Returns (indices into
    found_t, indices into true_t) of the pairs: the rest of found_t are extra, of true_t missed.
    """
    if found_t.size == 0 or true_t.size == 0:
        return np.empty(0, int), np.empty(0, int)
    j = np.clip(np.searchsorted(true_t, found_t), 1, true_t.size - 1)
    near = np.where(np.abs(true_t[j] - found_t) < np.abs(true_t[j - 1] - found_t), j, j - 1)
    half = np.minimum(np.diff(true_t, prepend=-np.inf), np.diff(true_t, append=np.inf))[near] / 2
    ok = np.abs(found_t - true_t[near]) < half
    found, true = np.flatnonzero(ok), near[ok]
    _, first = np.unique(true, return_index=True)  # a true impact claimed twice counts once
    return found[first], true[first]


def _train_numbers(times, t0, t1, omega, analysis):
    """Scalars of the noise study from :func:`impactosc.statistics.train_analysis.analyse_train`."""
    a = analyse_train(ImpactTrain(times, t0, t1, omega=omega), analysis, ("variability", "isi_density", "acf"))
    d = a["isi_density"]
    g, dens, mx = np.asarray(d["kde_grid"]), np.asarray(d["kde_density"]), np.asarray(d["maxima"])
    valley = float("nan")
    if mx.size >= 2:
        # depth of the bimodality: density minimum between the outer maxima / lower maximum
        inside = (g > mx[0]) & (g < mx[-1])
        valley = float(dens[inside].min() / min(np.interp(mx[0], g, dens), np.interp(mx[-1], g, dens)))
    return {
        "cv2_paper": a["variability"]["cv2_paper"],
        "cv2": a["variability"]["cv2"],
        "isi_n_modes": int(d["n_modes"]),
        "isi_maxima": " ".join(f"{m:.4f}" for m in mx),
        "isi_valley_ratio": valley,
        "acf_n_significant": int(a["acf"]["n_significant"]),
        "kde_grid": g,
        "kde_density": dens,
    }


def _extraction_row(rec, x_impact, truth, opts: ExtractOptions, noise=None) -> tuple[dict, np.ndarray]:
    """Extract the events of rec with the known x_impact and score them against the truth.

    Returns (columns, extracted impact times).  Timing: rms error, largest |error| / stated
    sigma_t, the share of errors within 2 stated sigma_t and the rms of error / sigma_t (0.95
    and 1 when sigma_t is honest).  The Cramer-Rao bound of each matched impact
    (:func:`impactosc.records.impact_times.crossing_time_crb`) is that of its fit's samples at
    the true crossing time and velocity, with the true noise ``noise`` (the estimate when None):
    its median and rms, and ``timing_crb_ratio`` = rms(error / bound) (1 when every impact is
    timed at its bound).  Penetration: median error and median |error| of the depths of the
    matched impacts.
    """
    T, V, Ht = truth["impacts"]["t"], truth["impacts"]["v"], depths_at_impacts(truth)
    ev, at = extract_events(rec, x_impact, opts)
    imp = ev["impacts"]
    E, s = imp["t"], imp["sigma_t"]
    fi, ti = match_impacts(T, E)
    err = E[fi] - T[ti]
    nan = float("nan")
    z = err / s[fi]
    row = {
        "n_true": T.size,
        "n_found": E.size,
        "missed": T.size - ti.size,
        "extra": E.size - fi.size,
        "timing_rms_s": float(np.sqrt(np.mean(err**2))) if err.size else nan,
        "timing_bias_s": float(np.median(err)) if err.size else nan,
        "timing_max_z": float(np.max(np.abs(z))) if err.size else nan,
        "frac_beyond_5sigma": float(np.mean(np.abs(z) > 5)) if err.size else nan,
        "timing_within_2sigma": float(np.mean(np.abs(z) < 2)) if err.size else nan,
        "timing_rms_z": float(np.sqrt(np.mean(z**2))) if err.size else nan,
        "sigma_t_median_s": at["timing_sigma_median"],
        "noise_estimate_m": at["noise_sigma"],
    }
    if err.size and "fit_samples" in imp:
        n = imp["fit_samples"][fi]
        centre = imp["fit_start"][fi] + (n - 1) / 2 * rec.dt
        sigma = at["noise_sigma"] if noise is None else noise
        bound = crossing_time_crb(sigma, V[ti], (T[ti] - centre) / rec.dt, n, imp["fit_degree"][fi])
        ok = np.isfinite(bound) & (bound > 0)
        if ok.any():
            row.update(
                timing_err_median_s=float(np.median(np.abs(err[ok]))),
                timing_crb_median_s=float(np.median(bound[ok])),
                timing_crb_rms_s=float(np.sqrt(np.mean(bound[ok] ** 2))),
                timing_crb_ratio=float(np.sqrt(np.mean((err[ok] / bound[ok]) ** 2))),
            )
    dh = ev["penetrations"]["h"][fi] - Ht[ti]
    dh = dh[np.isfinite(dh)]  # an impact whose contact's deepest point lies past the record's end
    if dh.size:
        row.update(penetration_bias_m=float(np.median(dh)), penetration_err_median_m=float(np.median(np.abs(dh))))
    return row, E


def _x_impact_columns(rec, span, x_true) -> dict:
    """Error and stated sigma of estimate_x_impact on the first ``span`` s of rec (nothing if span is 0)."""
    if not span:
        return {}
    n = int(np.searchsorted(rec.t, rec.t[0] + span, side="right"))
    part = Record(rec.t[:n], rec.x[:n], rec.omega, {}, rec.path)
    try:
        est, det = estimate_x_impact(part)
    except ValueError as exc:
        return {"x_impact_note": str(exc)}
    return {"x_impact_err_m": est - x_true, "x_impact_sigma_m": det["sigma"]}


def _realism_name(case: dict) -> str:
    """Method label of a realism row, e.g. 'realism: low-pass 500 Hz order 4, delay corrected'."""
    parts = []
    if case.get("quantum"):
        parts.append(f"ADC step {case['quantum'] * 1e6:g} um")
    if case.get("lowpass_hz"):
        how = "delay corrected" if case.get("declare_delay", True) else "delay not declared"
        parts.append(f"low-pass {case['lowpass_hz']:g} Hz order {case.get('lowpass_order', 4)}, {how}")
    if case.get("drift"):
        parts.append(f"zero drift {case['drift'] * 1e6:g} um over {case.get('drift_time', 10.0):g} s")
    if case.get("clock_jitter"):
        parts.append(f"clock jitter {case['clock_jitter'] * 1e6:g} us")
    return "realism: " + ("; ".join(parts) or "none")


def noise_study(
    omega,
    transient,
    duration,
    rates,
    noises,
    *,
    analysis=None,
    mismatch=None,
    seed=0,
    params=None,
    rtol=1e-10,
    atol=1e-12,
    x_impact_span=0.0,
    x_impact_noise=(),
    realism=None,
    realism_noise=5e-6,
    realism_rate=None,
):
    """How sampling rate, sensor noise and sensor imperfections change the extracted train.

    For each rate one simulation is sampled; for each noise level white noise is added,
    events are extracted twice (with hysteresis, and naive threshold crossing for
    comparison) and matched to the exact events.  Returns a list of row dicts (one per
    rate x noise x method, plus the exact train per rate) with the counts (true, found,
    missed, extra), the timing error (rms, median = bias, max |error| / stated sigma_t), the
    median stated sigma_t, the timing error against the Cramer-Rao bound
    (:func:`_extraction_row`), the penetration-depth error, and C_V^2 (paper and
    dimensionless), ISI modes / valley depth and significant ACF-spectrum peaks; the ISI
    kernel densities are returned under ``kde`` per row.

    x_impact_span : s; when > 0, the hysteresis row of every rate x noise also gets the error
        and stated sigma of :func:`estimate_x_impact` on the first x_impact_span s of the record
        (only at the noise levels in ``x_impact_noise`` when it is not empty).
    realism : list of dicts of :class:`SurrogateOptions` realism fields (lowpass_hz,
        lowpass_order, drift, drift_time, clock_jitter, quantum), one extra row each at
        ``realism_noise`` and ``realism_rate`` (default: the first rate), method
        ``"realism: ..."``, plus a ``"realism: none"`` row with the same noise draws.  A case
        with ``declare_delay: false`` drops the filter's sensor_delay from the record's metadata
        (the delay is then not corrected: its timing bias shows).
    """
    _check_x_impact_noise(noises, x_impact_noise)
    common = dict(mismatch=mismatch, seed=seed, params=params, rtol=rtol, atol=atol)
    out = []
    for rate in rates:
        rec0, truth = _clean_record(omega, transient, duration, rate, **common)
        out.append(_exact_row(rate, rec0, truth, omega, analysis))
        for noise, x in zip(noises, _noisy_samples(rec0.x, noises, seed)):
            out.extend(_level_rows(rate, noise, rec0, truth, x, omega, analysis, x_impact_span, x_impact_noise))
    if realism:
        out.extend(
            realism_rows(
                omega,
                transient,
                duration,
                float(realism_rate or rates[0]),
                realism_noise,
                realism,
                x_impact_span=x_impact_span,
                **common,
            )
        )
    return out


def _check_x_impact_noise(noises, x_impact_noise):
    """x_impact_noise must name levels of the study (an estimate at a level not studied is a typo)."""
    stray = sorted(set(x_impact_noise) - set(noises))
    if stray:
        raise ValueError(f"x_impact_noise {stray} not among the study's noise levels {list(noises)}")


def _clean_options(rate, mismatch, seed=0):
    """The surrogate's sensor at rate without noise (the study adds its own)."""
    return SurrogateOptions(rate=float(rate), noise=0.0, mismatch=mismatch or {}, seed=seed)


def _clean_record(omega, transient, duration, rate, *, mismatch, seed, params, rtol, atol):
    """The surrogate record sampled at rate without noise, and its exact events (the truth)."""
    base = _clean_options(rate, mismatch, seed)
    return surrogate_record(omega, transient, duration, base, params=params, rtol=rtol, atol=atol)


def _exact_row(rate, rec0, truth, omega, analysis) -> dict:
    """The row of the exact events of a rate's record: the statistics the extraction aims at."""
    T = truth["impacts"]["t"]
    exact = _train_numbers(T, float(rec0.t[0]), float(rec0.t[-1]), omega, analysis)
    return {
        "rate_hz": rate,
        "noise_m": 0.0,
        "method": "exact events",
        "n_true": T.size,
        "n_found": T.size,
        "missed": 0,
        "extra": 0,
        **exact,
    }


def _noisy_samples(x, noises, seed):
    """x plus white noise of each level in turn, from one generator seeded with seed: a level's
    draw follows those of the levels before it (a level of zero draws nothing)."""
    rng = np.random.default_rng(seed)
    for noise in noises:
        yield x + (rng.normal(0, noise, x.size) if noise > 0 else 0.0)


def _level_rows(rate, noise, rec0, truth, x, omega, analysis, x_impact_span, x_impact_noise) -> list[dict]:
    """The rows of one (rate, noise): events extracted with hysteresis and by naive threshold
    crossing, scored against the truth; the hysteresis row also gets the obstacle estimate at
    the levels of x_impact_noise (at every level when it is empty)."""
    # no omega: the study needs the impacts, not the Poincare points (the costliest
    # part of extraction left); the noise is estimated once for both methods
    rec = Record(rec0.t, x, None, rec0.meta, rec0.path)
    sigma = estimate_noise(x)
    t0, t1 = float(rec0.t[0]), float(rec0.t[-1])
    x_true = rec0.meta["x_impact"]
    out = []
    for method, opts in (
        ("hysteresis", ExtractOptions(noise=sigma)),
        ("naive threshold", ExtractOptions(noise=sigma, hysteresis=0.0, confirm_sigmas=0.0)),
    ):
        cols, E = _extraction_row(rec, x_true, truth, opts, noise if noise > 0 else None)
        row = {"rate_hz": rate, "noise_m": noise, "method": method, **cols}
        if method == "hysteresis" and (not x_impact_noise or noise in x_impact_noise):
            row.update(_x_impact_columns(Record(rec0.t, x, omega, {}, rec0.path), x_impact_span, x_true))
        try:
            row.update(_train_numbers(E, t0, t1, omega, analysis))
        except ValueError as exc:  # e.g. too few impacts left: say so in the table
            row["note"] = str(exc)
        out.append(row)
    return out


def realism_rows(
    omega,
    transient,
    duration,
    rate,
    noise,
    cases,
    *,
    mismatch=None,
    seed=0,
    params=None,
    rtol=1e-10,
    atol=1e-12,
    x_impact_span=0.0,
):
    """Rows of :func:`noise_study` for the sensor-realism cases (one simulation on the fine grid):
    a ``"realism: none"`` row, then one per case, all with the same noise draws."""
    for case in cases:
        unknown = set(case) - set(REALISM_FIELDS) - {"declare_delay"}
        if unknown:
            raise ValueError(f"unknown realism option(s) {sorted(unknown)}; known: {list(REALISM_FIELDS)}")
    p = mismatched_params(params, mismatch or {})
    # the fine grid of the anti-aliasing filter when a case has one
    k = SurrogateOptions(rate=rate, lowpass_hz=0.25 * rate).oversample if any(c.get("lowpass_hz") for c in cases) else 1
    win = Window(float(transient), float(transient) + float(duration), 1.0 / (rate * k))
    res = simulate(
        omega, transient, duration, params=p, rtol=rtol, atol=atol, window=win, record=("impacts", "penetrations")
    )
    truth, traj = res.events, res.trajectory
    coarse = {name: traj[name][::k] for name in ("t", "x", "v")}
    t = coarse["t"]
    out = []
    for case in [{}, *cases]:
        fields = {f: case[f] for f in REALISM_FIELDS if f in case}
        o = SurrogateOptions(rate=rate, noise=noise, mismatch=mismatch or {}, seed=seed, **fields)
        x = sensor_samples(traj if o.oversample > 1 else coarse, o, np.random.default_rng(seed))
        meta = surrogate_meta(o, p)
        if not case.get("declare_delay", True):
            meta.pop("sensor_delay", None)
        rec = Record(t, x, None, meta, "<surrogate>")
        cols, _ = _extraction_row(rec, p.xI, truth, ExtractOptions(noise=estimate_noise(x)))
        row = {"rate_hz": rate, "noise_m": noise, "method": _realism_name(case), **cols}
        if o.lowpass_hz > 0:  # the filter's delay, corrected or not (see the method)
            row["sensor_delay_s"] = o.sensor_delay
        xrec = Record(t - meta.get("sensor_delay", 0.0), x, omega, {}, "<surrogate>")
        row.update(_x_impact_columns(xrec, x_impact_span, p.xI))
        out.append(row)
    return out
