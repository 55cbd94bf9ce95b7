"""An impact train and the options of its analysis: the input of :mod:`impactosc.statistics.train_analysis`.

Why a module of its own: a train is impact onset times on a known observation span,
optionally with penetrations and the forcing frequency, whatever its source: a simulation
run file, a measured record written in the same HDF5 contract (:func:`load_train`), the
surrogate's extracted events or a benchmark run. Every consumer builds one here and hands
it, with :class:`AnalysisOptions`, to :func:`impactosc.statistics.train_analysis.analyse_train`.
Units: seconds, metres, rad/s.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactosc import statistics as st
from impactosc.io.files import read_run
from impactosc.statistics._validation import as_event_times, as_finite_1d

__all__ = ["AnalysisOptions", "ImpactTrain", "load_train"]


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
    lvr_refractoriness : float
        Refractoriness R of LvR, s (Shinomoto et al. 2009 and Elephant: 5 ms).
    serial_lags : int
        Lags 1..serial_lags of the intervals' serial correlation.
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
    lvr_refractoriness: float = 5e-3
    serial_lags: int = 10
    alpha: float = 0.05
    seed: int = 0

    def __post_init__(self):
        for name, low in (
            ("n_windows", 2),
            ("histogram_bins", 1),
            ("acf_kmax", 4),
            ("acf_n_peaks", 1),
            ("min_fano_windows", 2),
            ("serial_lags", 1),
        ):
            if int(getattr(self, name)) < low:
                raise ValueError(f"{name} must be >= {low}, got {getattr(self, name)}")
        if not 0 < self.alpha < 1:
            raise ValueError(f"alpha must be in (0, 1), got {self.alpha}")
        if not 0 <= self.min_prominence < 1 or not 0 <= self.acf_min_prominence < 1:
            raise ValueError("min_prominence and acf_min_prominence must be in [0, 1)")
        if not self.lvr_refractoriness >= 0:
            raise ValueError(f"lvr_refractoriness must be >= 0 s, got {self.lvr_refractoriness}")
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
    def from_config(cls, cfg: dict | None) -> AnalysisOptions:
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
            raise ValueError(f"impact times [{t[0]}, {t[-1]}] s lie outside the observation span [{a}, {b}] s")
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
    return ImpactTrain(t, a, b, penetrations=h, omega=omega, label=label or Path(path).stem, span_source=source)
