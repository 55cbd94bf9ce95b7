"""Section 2.2 of the paper (Figs 6-11): all statistics of one impact train, for any source.

Why: one function, :func:`analyse_train`, serves the model, every ensemble member, the
surrogate and measured records, so every panel and table row is computed the same way
whatever the train's origin (the train and the options are
:mod:`impactosc.statistics.impact_train`). It returns one JSON-ready dict of statistics
built on :mod:`impactosc.statistics`:

``train``         size, span, rate, mean ISI, forcing period
``stationarity``  counts in equal windows and the chi-square equal-rate test
``variability``   running paper C_V^2 (var/mean, s), dimensionless var/mean^2, Fano curve
``poisson``       KS test of the ISIs against the exponential law, Fano verdict
``isi_density``   10-bin relative-frequency histogram, kernel density and its maxima,
                  comparison with the forcing period, short/long interval composition
``mixture``       1..K-component mixtures (gaussian/lognormal/gamma), AIC/BIC ranking
``acf``           paper eq. (3) ACF, its spectrum, a shuffle-surrogate significance level
``penetrations``  histogram, kernel density and modes of the penetrations H_j
``local_variability``  beyond the paper: Holt's CV2, LV, LvR and the intervals' serial
                  correlations (:mod:`impactosc.statistics.local_variability`)

Units: seconds, metres, rad/s.  Curves are stored so figures are redrawn without
recomputing anything.  :func:`key_numbers` takes the scalars the ensemble and the table
use, :func:`ensemble_members` those of every re-run, :func:`mixture_table` the rows of
the ISI mixture table.

The rest of section 2.2 lives in its own modules, imported from there: the spread over
realisations (:mod:`impactosc.statistics.ensemble`), the Fig 6b spectrum
(:func:`impactosc.statistics.spectral_lines.trajectory_spectrum`), the rows of the paper table
(:func:`impactosc_study.paper.rows.chaotic.chaotic_rows`) and the statistics files
(:func:`impactosc.io.files.write_json`, :func:`~impactosc.io.files.read_json`).
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from pathlib import Path

import numpy as np

from impactosc import statistics as st
from impactosc.io.files import read_run
from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain, load_train

__all__ = [
    "PARTS",
    "ENSEMBLE_PARTS",
    "analyse_train",
    "key_numbers",
    "ensemble_members",
    "mixture_table",
]

PARTS = ("stationarity", "variability", "poisson", "isi_density", "mixture", "acf", "penetrations", "local_variability")


# ----------------------------------------------------------------------------- parts


def _stationarity(train: ImpactTrain, o: AnalysisOptions) -> dict:
    counts = st.window_counts(train.times, train.t_start, train.t_stop, o.n_windows)
    test = st.equal_rate_test(counts, alpha=o.alpha)
    return {
        "window_length": train.duration / o.n_windows,
        "counts": counts,
        "chi2": test.statistic,
        "dof": test.dof,
        "pvalue": test.pvalue,
        "rejected": test.rejected,
        "conclusion": test.conclusion,
    }


def _fano(train: ImpactTrain, o: AnalysisOptions) -> dict:
    """Fano factor against window length with the Poisson (F = 1) acceptance band."""
    fit = [w for w in o.fano_windows if train.duration / w >= o.min_fano_windows]
    if not fit:
        raise ValueError(f"no Fano window fits {o.min_fano_windows} times into the {train.duration} s span")
    curve = st.fano_curve(train.times, fit, train.t_start, train.t_stop)
    dof = curve.n_windows - 1
    from scipy import stats as sps

    lo = sps.chi2.ppf(o.alpha / 2, dof) / dof
    hi = sps.chi2.ppf(1 - o.alpha / 2, dof) / dof
    below = curve.fano < lo
    return {
        "windows": curve.windows,
        "fano": curve.fano,
        "n_windows": curve.n_windows,
        "poisson_low": lo,
        "poisson_high": hi,
        "below_poisson": below,
        "conclusion": (
            f"Fano factor below the Poisson {100 * (1 - o.alpha):.0f}% band for "
            f"{int(below.sum())} of {below.size} window lengths "
            f"({min(fit):g}..{max(fit):g} s; F = {curve.fano.min():.3g}..{curve.fano.max():.3g})"
        ),
    }


def _variability(train: ImpactTrain, o: AnalysisOptions) -> dict:
    S = train.intervals
    paper = st.cv2_paper_running(S)
    dimless = st.cv2_running(S)
    return {
        "sample_size": paper.sample_size,
        "cv2_paper_running": paper.value,
        "cv2_running": dimless.value,
        "cv2_paper": paper.final,
        "cv2": dimless.final,
        "cv2_paper_units": "s",
        "fano": _fano(train, o),
    }


def _poisson(train: ImpactTrain, o: AnalysisOptions) -> dict:
    ks = st.exponential_ks_test(train.intervals, alpha=o.alpha, n_bootstrap=o.ks_bootstrap, seed=o.seed)
    return {
        "ks_statistic": ks.statistic,
        "pvalue": ks.pvalue,
        "pvalue_ks": ks.pvalue_ks,
        "pvalue_bootstrap": ks.pvalue_bootstrap,
        "rejected": ks.rejected,
        "conclusion": ks.conclusion,
    }


def _density(values, o: AnalysisOptions) -> dict:
    """Histogram, kernel density and its maxima: the shared core of Figs 9 and 11."""
    hist = st.relative_frequency_histogram(values, bins=o.histogram_bins)
    kde = st.kernel_density(values, bw_method=o.kde_bandwidth)
    mx = st.density_maxima(kde.grid, kde.density, min_prominence=o.min_prominence)
    rf = hist.relative_frequency
    padded = np.concatenate([[-1.0], rf, [-1.0]])
    bar_max = np.flatnonzero((padded[1:-1] > padded[:-2]) & (padded[1:-1] > padded[2:]))
    return {
        "n": int(np.size(values)),
        "histogram_edges": hist.edges,
        "histogram_relative_frequency": rf,
        "bin_width": float(hist.widths[0]),
        "histogram_local_maxima": hist.centers[bar_max],
        "kde_grid": kde.grid,
        "kde_density": kde.density,
        "kde_bandwidth": kde.bandwidth,
        "maxima": mx.positions,
        "maxima_density": mx.heights,
        "maxima_relative_height": mx.heights / mx.heights.max() if mx.n_modes else np.empty(0),
        "n_modes": mx.n_modes,
    }


def _isi_density(train: ImpactTrain, o: AnalysisOptions) -> dict:
    S = train.intervals
    out = _density(S, o)
    mx = out["maxima"]
    if train.omega is not None:
        period = 2 * np.pi / train.omega
        dist = np.abs(mx - period)
        j = int(np.argmin(dist)) if mx.size else -1
        out["forcing_period"] = period
        out["forcing_nearest_maximum"] = float(mx[j]) if j >= 0 else None
        out["forcing_distance"] = float(dist[j]) if j >= 0 else None
        out["forcing_is_maximum"] = bool(j >= 0 and dist[j] <= out["bin_width"])
        out["forcing_relative_density"] = float(
            np.interp(period, out["kde_grid"], out["kde_density"]) / out["kde_density"].max()
        )
    if mx.size >= 2:
        # the two highest maxima define a short and a long interval scale; the density
        # minimum between them splits the intervals into the two classes
        top = np.sort(np.argsort(out["maxima_density"])[-2:])
        a, b = mx[top[0]], mx[top[1]]
        g, d = out["kde_grid"], out["kde_density"]
        inside = (g > a) & (g < b)
        split = float(g[inside][np.argmin(d[inside])])
        short = split > S
        sym = "".join("s" if x else "L" for x in short)
        triples = Counter(sym[i : i + 3] for i in range(len(sym) - 2))
        out["scales"] = {
            "split": split,
            "short_fraction": float(short.mean()),
            "mean_short": float(S[short].mean()),
            "mean_long": float(S[~short].mean()),
            "triples": dict(triples.most_common()),
        }
    return out


def _mixture_curves(fit: st.MixtureFit, grid: np.ndarray) -> dict:
    comps = []
    for j in range(fit.n_components):
        one = dataclasses.replace(fit, weights=np.array([1.0]), params={k: v[[j]] for k, v in fit.params.items()})
        comps.append(fit.weights[j] * one.pdf(grid))
    return {"pdf": fit.pdf(grid), "components": np.array(comps)}


def _fit_record(fit: st.MixtureFit) -> dict:
    return {
        "family": fit.family,
        "n_components": fit.n_components,
        "weights": fit.weights,
        "params": dict(fit.params),
        "means": fit.means,
        "stds": fit.stds,
        "modes": fit.modes,
        "loglik": fit.loglik,
        "aic": fit.aic,
        "bic": fit.bic,
        "converged": fit.converged,
    }


def _mixture(train: ImpactTrain, o: AnalysisOptions, grid: np.ndarray) -> dict:
    sel = st.select_mixture(
        train.intervals,
        families=o.mixture_families,
        n_components=o.mixture_components,
        n_restarts=o.mixture_restarts,
        seed=o.seed,
    )
    fits = list(sel.fits)
    aic0 = min(f.aic for f in fits)
    records = []
    for f, dbic in zip(fits, sel.delta_bic):
        rec = _fit_record(f)
        rec["delta_bic"] = float(dbic)
        rec["delta_aic"] = f.aic - aic0
        records.append(rec)
    best_by_k = {}
    for f in fits:  # fits are sorted by BIC, so the first of each K is its best
        best_by_k.setdefault(f.n_components, f)
    out = {
        "fits": records,
        "best": f"{fits[0].family} x{fits[0].n_components}",
        "best_aic": f"{min(fits, key=lambda f: f.aic).family} x{min(fits, key=lambda f: f.aic).n_components}",
        "best_by_k": {str(k): f"{f.family} x{k}" for k, f in sorted(best_by_k.items())},
        "grid": grid,
        "curves": {f"{f.family} x{k}": _mixture_curves(f, grid) for k, f in sorted(best_by_k.items())},
    }
    if 1 in best_by_k and 2 in best_by_k:
        out["delta_bic_2_vs_1"] = best_by_k[1].bic - best_by_k[2].bic
        out["delta_aic_2_vs_1"] = best_by_k[1].aic - best_by_k[2].aic
    return out


def _acf(train: ImpactTrain, o: AnalysisOptions, scales: dict | None) -> dict:
    S = train.intervals
    kmax = int(min(o.acf_kmax, S.size // 2))
    acf = st.autocorrelation(S, kmax=kmax)
    spec = st.acf_spectrum(acf, n_peaks=o.acf_n_peaks, min_prominence=o.acf_min_prominence)
    threshold = None
    if o.acf_surrogates:
        # Shuffling keeps the ISI distribution and destroys the order: the (1 - alpha)
        # quantile of the largest spectral value (f > 0) of shuffled trains is the level a
        # peak must exceed to be a periodicity of the sequence rather than noise.
        # The surrogate statistic is measured like the data's peaks (refined peak height,
        # same prominence rule; the largest value at f > 0 if no peak qualifies).
        rng = np.random.default_rng(o.seed)
        top = []
        for value in st.shuffled_autocorrelations(S, kmax, o.acf_surrogates, rng):
            sp = st.acf_spectrum(value, n_peaks=1, min_prominence=o.acf_min_prominence)
            top.append(sp.peak_magnitude[0] if sp.peak_magnitude.size else sp.magnitude[1:].max())
        threshold = float(np.quantile(top, 1 - o.alpha))
    sig = (spec.peak_magnitude > threshold) if threshold is not None else np.zeros(spec.peak_frequency.size, bool)
    mean = float(S.mean())
    out = {
        "k": acf.k,
        "value": acf.value,
        "noise_level": 2 / math.sqrt(S.size),
        "frequency": spec.frequency,
        "magnitude": spec.magnitude,
        "peak_frequency": spec.peak_frequency,
        "peak_magnitude": spec.peak_magnitude,
        "peak_period_intervals": spec.peak_period,
        "peak_period_s": mean * spec.peak_period,
        "surrogate_level": threshold,
        "significant": sig,
        "n_significant": int(sig.sum()),
        "mean_isi": mean,
    }
    if scales is not None and spec.peak_frequency.size:
        # the strongest periodicity in intervals, spelt out in short and long intervals
        p = int(round(float(spec.peak_period[0])))
        n_short = int(round(p * scales["short_fraction"]))
        out["strongest_pattern"] = {
            "intervals": p,
            "n_short": n_short,
            "n_long": p - n_short,
            "duration_s": n_short * scales["mean_short"] + (p - n_short) * scales["mean_long"],
        }
    return out


def _penetrations(train: ImpactTrain, o: AnalysisOptions) -> dict | None:
    h = train.penetrations
    if h is None or h.size < 10 or np.ptp(h) == 0:
        return None
    out = _density(h, o)
    if out["n_modes"]:
        out["main_mode"] = float(out["maxima"][np.argmax(out["maxima_density"])])
        out["main_is_deepest"] = bool(out["main_mode"] == out["maxima"].max())
    return out


def _local_variability(train: ImpactTrain, o: AnalysisOptions) -> dict:
    """Beyond the paper: the local measures that stay valid when the rate drifts, and the serial
    correlations, with 2/sqrt(n), the 95 % band of a correlation of independent intervals."""
    S = train.intervals
    lags = int(min(o.serial_lags, S.size - 3))
    return {
        "holt_cv2": st.holt_cv2(S),
        "lv": st.local_variation(S),
        "lvr": st.revised_local_variation(S, o.lvr_refractoriness),
        "lvr_refractoriness": o.lvr_refractoriness,
        "serial_lags": np.arange(1, lags + 1),
        "serial_correlation": st.serial_correlation(S, lags),
        "serial_noise_level": 2 / math.sqrt(S.size),
    }


def analyse_train(train: ImpactTrain, options: AnalysisOptions | None = None, parts=PARTS) -> dict:
    """All section-2.2 statistics of one impact train, as a JSON-ready dict.

    Why: one function serves the model, the ensemble members and measured records, so
    every panel and table row is computed the same way whatever the train's origin.

    Parameters
    ----------
    train : ImpactTrain
    options : AnalysisOptions, optional
    parts : sequence of str
        Subset of :data:`PARTS` to compute (the ensemble skips the slow ones).

    Returns
    -------
    dict
        Keys ``train``, ``options`` and one per computed part (see module docstring);
        numpy arrays are converted to lists by :func:`impactosc.io.files.write_json`.
    """
    o = options or AnalysisOptions()
    unknown = set(parts) - set(PARTS)
    if unknown:
        raise ValueError(f"unknown part(s) {sorted(unknown)}; choose from {PARTS}")
    S = train.intervals
    out = {
        "train": {
            "label": train.label,
            "n_impacts": int(train.times.size),
            "n_intervals": int(S.size),
            "t_start": train.t_start,
            "t_stop": train.t_stop,
            "duration": train.duration,
            "span_source": train.span_source,
            "rate": train.times.size / train.duration,
            "mean_isi": float(S.mean()),
            "omega": train.omega,
            "forcing_period": 2 * np.pi / train.omega if train.omega else None,
            "has_penetrations": train.penetrations is not None,
        },
        "options": dataclasses.asdict(o),
    }
    if "stationarity" in parts:
        out["stationarity"] = _stationarity(train, o)
    if "variability" in parts:
        out["variability"] = _variability(train, o)
    if "poisson" in parts:
        out["poisson"] = _poisson(train, o)
    dens = _isi_density(train, o) if ("isi_density" in parts or "mixture" in parts) else None
    if "isi_density" in parts:
        out["isi_density"] = dens
    if "mixture" in parts:
        out["mixture"] = _mixture(train, o, dens["kde_grid"])
    if "acf" in parts:
        out["acf"] = _acf(train, o, dens.get("scales") if dens else None)
    if "penetrations" in parts:
        out["penetrations"] = _penetrations(train, o)
    if "local_variability" in parts:
        out["local_variability"] = _local_variability(train, o)
    return out


# ------------------------------------------------------------------ summaries, tables


def key_numbers(stats: dict) -> dict:
    """The scalar results of :func:`analyse_train` that the table and the ensemble use."""
    out = {"n_impacts": stats["train"]["n_impacts"], "rate": stats["train"]["rate"]}
    if "stationarity" in stats:
        out["window_counts"] = list(np.asarray(stats["stationarity"]["counts"]).tolist())
        out["equal_rate_p"] = stats["stationarity"]["pvalue"]
    if "variability" in stats:
        out["cv2_paper"] = stats["variability"]["cv2_paper"]
        out["cv2"] = stats["variability"]["cv2"]
    if "isi_density" in stats:
        m = np.asarray(stats["isi_density"]["maxima"], dtype=float)
        out["isi_n_maxima"] = int(m.size)
        out["isi_first_maximum"] = float(m[0]) if m.size else None
        out["isi_last_maximum"] = float(m[-1]) if m.size else None
    if "mixture" in stats:
        out["mixture_best"] = stats["mixture"]["best"]
        out["mixture_best_2"] = stats["mixture"]["best_by_k"].get("2")
    if "acf" in stats:
        f = np.asarray(stats["acf"]["peak_frequency"], dtype=float)
        sig = np.asarray(stats["acf"]["significant"], dtype=bool)
        out["acf_peak_frequency"] = float(f[0]) if f.size else None
        out["acf_second_frequency"] = float(f[1]) if f.size > 1 else None
        out["acf_second_significant"] = bool(sig[1]) if sig.size > 1 else False
        out["acf_n_significant"] = stats["acf"]["n_significant"]
    if stats.get("penetrations"):
        out["penetration_n_modes"] = stats["penetrations"]["n_modes"]
    if "local_variability" in stats:
        loc = stats["local_variability"]
        out.update(holt_cv2=loc["holt_cv2"], lv=loc["lv"], lvr=loc["lvr"])
        out["serial_correlation_1"] = float(np.asarray(loc["serial_correlation"])[0])
    return out


#: Parts computed for every ensemble member (the KS bootstrap is left out: its p-value is
#: at the bootstrap floor for every chaotic run and it is the slowest part).
ENSEMBLE_PARTS = ("stationarity", "variability", "isi_density", "mixture", "acf", "penetrations", "local_variability")


def ensemble_members(paths, options: AnalysisOptions | None = None) -> dict:
    """Key numbers of each run file, keyed by file stem, with the run's rtol and x(0).

    Why: the ensemble of re-runs (other tolerances, other initial states) gives the
    spread that every compared number is judged against.
    """
    members = {}
    for path in paths:
        _, attrs, _ = read_run(path)
        stats = analyse_train(load_train(path), options, parts=ENSEMBLE_PARTS)
        k = {"rtol": attrs.get("rtol"), "x0": attrs.get("x0")}
        k.update(key_numbers(stats))
        name = Path(path).stem
        if name in members:
            raise ValueError(f"two ensemble runs share the name {name!r}")
        members[name] = k
    return members


def mixture_table(stats: dict) -> list[dict]:
    """One row per mixture fit (best BIC first), for results/tables/chaotic/isi_mixture.csv."""
    rows = []
    for f in stats["mixture"]["fits"]:
        fmt = lambda a, spec: " ".join(format(float(v), spec) for v in a)
        rows.append(
            {
                "family": f["family"],
                "components": f["n_components"],
                "weights": fmt(f["weights"], ".3f"),
                "means_s": fmt(f["means"], ".4f"),
                "stds_s": fmt(f["stds"], ".4f"),
                "modes_s": fmt(f["modes"], ".4f"),
                "params": "; ".join(f"{k}=" + fmt(v, ".4g") for k, v in f["params"].items()),
                "loglik": f"{f['loglik']:.2f}",
                "aic": f"{f['aic']:.2f}",
                "bic": f"{f['bic']:.2f}",
                "delta_aic": f"{f['delta_aic']:.2f}",
                "delta_bic": f"{f['delta_bic']:.2f}",
                "converged": f["converged"],
            }
        )
    return rows
