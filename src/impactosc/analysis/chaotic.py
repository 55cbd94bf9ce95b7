"""Train-level analysis of an impact train (paper section 2.2, Figs 6-11), for any source.

An :class:`ImpactTrain` is impact onset times on a known observation span, optionally
with penetrations and the forcing frequency.  It can come from a simulation run file or
from a measured record written in the same HDF5 contract (:func:`load_train`), so the
experimental path reuses this module untouched.  :func:`analyse_train` turns a train into
one JSON-ready dict of statistics built on :mod:`impactosc.statistics`:

``train``         size, span, rate, mean ISI, forcing period
``stationarity``  counts in equal windows and the chi-square equal-rate test
``variability``   running paper C_V^2 (var/mean, s), dimensionless var/mean^2, Fano curve
``poisson``       KS test of the ISIs against the exponential law, Fano verdict
``isi_density``   10-bin relative-frequency histogram, kernel density and its maxima,
                  comparison with the forcing period, short/long interval composition
``mixture``       1..K-component mixtures (gaussian/lognormal/gamma), AIC/BIC ranking
``acf``           paper eq. (3) ACF, its spectrum, a shuffle-surrogate significance level
``penetrations``  histogram, kernel density and modes of the penetrations H_j

Units: seconds, metres, rad/s.  Curves are stored so figures are redrawn without
recomputing anything.  :func:`paper_rows` compares the model numbers with the paper.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import stats as sps

from .. import statistics as st
from ..files import read_json, read_run, write_csv, write_json
from ..paper.rows import chaotic_rows as paper_rows
from ..statistics._validation import as_event_times, as_finite_1d

__all__ = [
    "PARTS",
    "AnalysisOptions",
    "ImpactTrain",
    "load_train",
    "analyse_train",
    "key_numbers",
    "ENSEMBLE_PARTS",
    "ensemble_runs",
    "ensemble_members",
    "ensemble_summary",
    "ensemble_table",
    "trajectory_spectrum",
    "mixture_table",
    "paper_rows",
    "write_json",
    "read_json",
    "write_csv",
]

PARTS = ("stationarity", "variability", "poisson", "isi_density", "mixture", "acf", "penetrations")


@dataclass(frozen=True)
class AnalysisOptions:
    """Settings of :func:`analyse_train` (the ``chaotic.analysis`` config section).

    Attributes
    ----------
    n_windows : int
        Equal windows for the stationarity test (paper: 5 x 80 s).
    histogram_bins : int
        Bars of the ISI and penetration histograms (paper: 10).
    kde_bandwidth : str or float
        ``gaussian_kde`` bandwidth rule ("scott", "silverman") or factor.
    min_prominence : float
        Relative prominence a density maximum needs to count as a mode.
    fano_windows : tuple of float
        Counting-window lengths (s) of the Fano curve; lengths that fit fewer than
        ``min_fano_windows`` times into the span are skipped.
    min_fano_windows : int
    acf_kmax : int
        Largest paper index k of the ACF (lags 0 .. kmax-1); capped at n // 2.
    acf_n_peaks : int
        ACF-spectrum peaks reported (paper: 2).
    acf_min_prominence : float
        Relative prominence of an ACF-spectrum peak.
    acf_surrogates : int
        Shuffled-ISI surrogates for the significance level of the ACF spectrum (0: none).
    mixture_families : tuple of str
    mixture_components : tuple of int
    mixture_restarts : int
    ks_bootstrap : int
        Bootstrap replicates of the exponential KS test.
    alpha : float
        Significance level of every test.
    seed : int
        Seed of every random step (surrogates, bootstrap, EM restarts).
    """

    n_windows: int = 5
    histogram_bins: int = 10
    kde_bandwidth: str | float = "scott"
    min_prominence: float = 0.05
    fano_windows: tuple = (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 80.0)
    min_fano_windows: int = 4
    acf_kmax: int = 50
    acf_n_peaks: int = 2
    acf_min_prominence: float = 0.05
    acf_surrogates: int = 200
    mixture_families: tuple = st.FAMILIES
    mixture_components: tuple = (1, 2, 3)
    mixture_restarts: int = 8
    ks_bootstrap: int = 999
    alpha: float = 0.05
    seed: int = 0

    def __post_init__(self):
        for name, low in (("n_windows", 2), ("histogram_bins", 1), ("acf_kmax", 4),
                          ("acf_n_peaks", 1), ("min_fano_windows", 2)):
            if int(getattr(self, name)) < low:
                raise ValueError(f"{name} must be >= {low}, got {getattr(self, name)}")
        if not 0 < self.alpha < 1:
            raise ValueError(f"alpha must be in (0, 1), got {self.alpha}")
        if not 0 <= self.min_prominence < 1 or not 0 <= self.acf_min_prominence < 1:
            raise ValueError("min_prominence and acf_min_prominence must be in [0, 1)")
        if self.acf_surrogates < 0 or self.ks_bootstrap < 0:
            raise ValueError("acf_surrogates and ks_bootstrap must be >= 0")
        if not self.fano_windows or min(self.fano_windows) <= 0:
            raise ValueError(f"fano_windows must be positive lengths in s, got {self.fano_windows}")
        if not self.mixture_components or min(self.mixture_components) < 1:
            raise ValueError(f"mixture_components must be >= 1, got {self.mixture_components}")
        unknown = set(self.mixture_families) - set(st.FAMILIES)
        if unknown or not self.mixture_families:
            raise ValueError(f"mixture_families must be a subset of {st.FAMILIES}, got {self.mixture_families}")
        # lists from a YAML config become tuples, so options stay hashable and comparable
        for name in ("fano_windows", "mixture_families", "mixture_components"):
            object.__setattr__(self, name, tuple(getattr(self, name)))

    @classmethod
    def from_config(cls, cfg: dict | None) -> "AnalysisOptions":
        """Options from a config dict; unknown keys raise ValueError naming them."""
        cfg = dict(cfg or {})
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = set(cfg) - known
        if unknown:
            raise ValueError(f"unknown analysis option(s) {sorted(unknown)}; known: {sorted(known)}")
        return cls(**cfg)


@dataclass(frozen=True)
class ImpactTrain:
    """Impact onset times observed on ``[t_start, t_stop]`` (s).

    Attributes
    ----------
    times : ndarray
        Impact onset times T_j (s), strictly increasing, inside the span, at least 10.
    t_start, t_stop : float
        Observation span (s); windows and Fano counts tile it (not first/last impact).
    penetrations : ndarray or None
        Maximal penetrations H_j (m), >= 0.
    omega : float or None
        Forcing frequency (rad/s), for comparing time scales with 2 pi / omega.
    label : str
        Name shown in figures and tables (e.g. "model", "surrogate").
    span_source : str
        Where the span came from (attributes or the impact times).
    """

    times: np.ndarray
    t_start: float
    t_stop: float
    penetrations: np.ndarray | None = None
    omega: float | None = None
    label: str = "train"
    span_source: str = "given"

    def __post_init__(self):
        t = as_event_times(self.times, "times", min_size=10)
        a, b = float(self.t_start), float(self.t_stop)
        if not (math.isfinite(a) and math.isfinite(b)) or b <= a:
            raise ValueError(f"observation span must satisfy t_start < t_stop, got [{a}, {b}]")
        if t[0] < a or t[-1] > b:
            raise ValueError(
                f"impact times [{t[0]}, {t[-1]}] s lie outside the observation span [{a}, {b}] s"
            )
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "t_start", a)
        object.__setattr__(self, "t_stop", b)
        if self.penetrations is not None:
            h = as_finite_1d(self.penetrations, "penetrations")
            if np.any(h < 0):
                raise ValueError("penetrations must be >= 0 m")
            object.__setattr__(self, "penetrations", h)
        if self.omega is not None:
            w = float(self.omega)
            if not math.isfinite(w) or w <= 0:
                raise ValueError(f"omega must be a positive frequency in rad/s, got {self.omega!r}")
            object.__setattr__(self, "omega", w)

    @property
    def intervals(self) -> np.ndarray:
        """Inter-impact intervals S_j (s)."""
        return np.diff(self.times)

    @property
    def duration(self) -> float:
        """Length of the observation span (s)."""
        return self.t_stop - self.t_start


def load_train(path, label: str | None = None) -> ImpactTrain:
    """Read an impact train from an HDF5 run file (simulated or measured, io contract).

    Needs ``impacts/t``; uses ``penetrations/h`` and the ``omega`` attribute if present.
    The span is taken, in this order, from attributes ``t_start``/``t_stop``, from
    ``transient`` and ``transient + duration`` (simulation runs), or else from the first and
    last impact (recorded in ``span_source``; it biases window counts slightly).
    """
    events, attrs, _ = read_run(path)
    if "impacts" not in events or "t" not in events["impacts"]:
        raise ValueError(f"{path}: no impacts/t dataset; not an impact-train file")
    t = np.asarray(events["impacts"]["t"], dtype=float)
    if "t_start" in attrs and "t_stop" in attrs:
        a, b, source = float(attrs["t_start"]), float(attrs["t_stop"]), "attributes t_start/t_stop"
    elif "transient" in attrs and "duration" in attrs:
        a = float(attrs["transient"])
        b, source = a + float(attrs["duration"]), "attributes transient/duration"
    elif t.size:
        a, b, source = float(t[0]), float(t[-1]), "first and last impact"
    else:
        raise ValueError(f"{path}: the file holds no impacts")
    h = events.get("penetrations", {}).get("h")
    omega = attrs.get("omega")
    return ImpactTrain(t, a, b, penetrations=h, omega=omega,
                       label=label or Path(path).stem, span_source=source)


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
        raise ValueError(
            f"no Fano window fits {o.min_fano_windows} times into the {train.duration} s span"
        )
    curve = st.fano_curve(train.times, fit, train.t_start, train.t_stop)
    dof = curve.n_windows - 1
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
        short = S < split
        sym = "".join("s" if x else "L" for x in short)
        triples = Counter(sym[i:i + 3] for i in range(len(sym) - 2))
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
        one = dataclasses.replace(fit, weights=np.array([1.0]),
                                  params={k: v[[j]] for k, v in fit.params.items()})
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
    sel = st.select_mixture(train.intervals, families=o.mixture_families,
                            n_components=o.mixture_components, n_restarts=o.mixture_restarts,
                            seed=o.seed)
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
        for _ in range(o.acf_surrogates):
            sp = st.acf_spectrum(st.autocorrelation(rng.permutation(S), kmax=kmax), n_peaks=1,
                                 min_prominence=o.acf_min_prominence)
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


def analyse_train(train: ImpactTrain, options: AnalysisOptions | None = None,
                  parts=PARTS) -> dict:
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
        numpy arrays are converted to lists by :func:`write_json`.
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
    return out


# ------------------------------------------------------------------ spectrum (Fig. 6)

def trajectory_spectrum(t, x, omega: float, n_peaks: int = 5, low_band: float = 0.9) -> dict:
    """Amplitude spectrum of x(t) with its dominant line and low-frequency content (Fig. 6b).

    Why: the paper reports one dominant peak at the forcing frequency and a dense set of
    lower frequencies; this measures both (peak frequency and the share of the signal
    power below ``low_band * omega``).

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled time (s) and displacement (m).
    omega : float
        Forcing frequency (rad/s).
    n_peaks : int
        Strongest lines reported.
    low_band : float
        Upper edge of the low-frequency band as a fraction of omega.
    """
    t = as_event_times(t, "t", min_size=8)
    dt = np.diff(t)
    if not np.allclose(dt, dt[0], rtol=1e-6, atol=0):
        raise ValueError("trajectory must be uniformly sampled")
    spec = st.amplitude_spectrum(x, float(dt[0]))
    peaks = st.find_peaks_spectrum(spec, n_peaks=n_peaks)
    power = spec.amplitude**2
    total = power[1:].sum()
    low = power[1:][spec.omega[1:] < low_band * omega].sum()
    return {
        "spectrum": spec,
        "peak_omega": peaks.omega,
        "peak_amplitude": peaks.amplitude,
        "dominant_omega": float(peaks.omega[0]),
        "d_omega": spec.d_omega,
        "dominant_to_next": float(peaks.amplitude[0] / peaks.amplitude[1]) if peaks.omega.size > 1 else None,
        "low_band": low_band,
        "low_power_fraction": float(low / total),
    }


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
    return out


#: Parts computed for every ensemble member (the KS bootstrap is left out: its p-value is
#: at the bootstrap floor for every chaotic run and it is the slowest part).
ENSEMBLE_PARTS = ("stationarity", "variability", "isi_density", "mixture", "acf", "penetrations")


def ensemble_runs(scene: dict, solver: dict, ensemble: dict) -> dict:
    """Re-runs of a scene that differ only in tolerance or x(0): name -> rtol, atol, x0.

    Why: each is an independent realisation of the attractor (a chaotic trajectory
    decorrelates within seconds), so together they measure the realisation spread.  atol
    is scaled with rtol in the solver's ratio; names are unique and file-name safe.

    Parameters
    ----------
    scene : dict
        Scene config (uses ``x0``, default 0).
    solver : dict
        ``rtol`` and ``atol`` of the scene run.
    ensemble : dict
        ``rtol`` (list of tolerances) and ``x0`` (list of initial displacements, m).
    """
    ratio = solver["atol"] / solver["rtol"]
    runs = {}
    for rtol in ensemble.get("rtol", []):
        runs[f"rtol{rtol:.0e}"] = {"rtol": rtol, "atol": rtol * ratio, "x0": scene.get("x0", 0.0)}
    for x0 in ensemble.get("x0", []):
        runs[f"x0{x0:+.1e}"] = {"rtol": solver["rtol"], "atol": solver["atol"], "x0": x0}
    n = len(ensemble.get("rtol", [])) + len(ensemble.get("x0", []))
    if len(runs) != n:
        raise ValueError("ensemble tolerances or initial states repeat (after rounding to names)")
    return runs


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


def ensemble_table(members: dict) -> list[dict]:
    """One row per ensemble member for a CSV (lists joined by spaces)."""
    rows = []
    for name, k in members.items():
        row = {"run": name}
        for key, v in k.items():
            row[key] = " ".join(str(x) for x in v) if isinstance(v, list) else v
        rows.append(row)
    return rows


def ensemble_summary(members: dict) -> dict:
    """Spread of key numbers over realisations of the same attractor.

    Why: a chaotic train reproduces statistics, not exact counts; runs that differ only
    in tolerance or initial state are independent realisations, and their spread is the
    honest uncertainty of every number compared with the paper.

    Parameters
    ----------
    members : dict of str -> dict
        Member name -> :func:`key_numbers` output (at least 2 members).

    Returns
    -------
    dict
        ``members`` (as given), ``numeric`` (name -> mean, sd, min, max, n) for scalar
        numbers (run settings ``rtol`` and ``x0`` excluded), ``window_counts`` (all windows pooled: mean, sd) and ``categorical``
        (name -> value counts).
    """
    if len(members) < 2:
        raise ValueError(f"an ensemble needs at least 2 members, got {len(members)}")
    names = sorted({k for m in members.values() for k in m} - {"rtol", "x0"})
    numeric, categorical = {}, {}
    for k in names:
        vals = [m.get(k) for m in members.values() if m.get(k) is not None]
        if not vals or isinstance(vals[0], list):
            continue
        if isinstance(vals[0], str):
            categorical[k] = dict(Counter(vals))
        else:
            a = np.asarray(vals, dtype=float)
            numeric[k] = {"mean": float(a.mean()), "sd": float(a.std(ddof=1)) if a.size > 1 else 0.0,
                          "min": float(a.min()), "max": float(a.max()), "n": int(a.size)}
    out = {"members": members, "numeric": numeric, "categorical": categorical}
    wc = [m["window_counts"] for m in members.values() if "window_counts" in m]
    if wc:
        w = np.asarray(wc, dtype=float).ravel()
        out["window_counts"] = {"mean": float(w.mean()), "sd": float(w.std(ddof=1)), "n": int(w.size)}
    return out


def mixture_table(stats: dict) -> list[dict]:
    """One row per mixture fit (best BIC first), for results/tables/isi_mixture.csv."""
    rows = []
    for f in stats["mixture"]["fits"]:
        fmt = lambda a, spec: " ".join(format(float(v), spec) for v in a)  # noqa: E731
        rows.append({
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
        })
    return rows
