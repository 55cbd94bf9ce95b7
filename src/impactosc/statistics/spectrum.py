"""Amplitude spectrum of a sampled signal, its peaks, and combination-frequency labels.

Paper Fig. 4c: after the grazing bifurcation at w = 23.03 rad/s the spectrum of x(t) has,
besides the harmonics k*w, a frequency w1 < w and the combinations labelled a, b, c, d, f
(w -/+ w1, 2w -/+ w1, 3w - w1).  Fig. 6b: the chaotic spectrum has one dominant peak at w.
Frequencies are reported both as angular frequency (rad/s, the paper's unit) and in Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._peaks import parabolic_refine
from impactosc.statistics._validation import as_finite_1d, check_positive_scalar

__all__ = [
    "PAPER_COMBINATIONS",
    "Spectrum",
    "SpectralPeaks",
    "CombinationLabel",
    "SecondaryFrequency",
    "amplitude_spectrum",
    "find_peaks_spectrum",
    "label_combinations",
    "estimate_secondary_frequency",
]

#: Paper Fig. 4c labels -> (k, m) meaning the frequency k*w + m*w1.  The caption lists
#: "w +/- w1, 2w +/- w1, and 3w - w1" for a, b, c, d, f; we take them in that order.
PAPER_COMBINATIONS = {"a": (1, -1), "b": (1, 1), "c": (2, -1), "d": (2, 1), "f": (3, -1)}


@dataclass(frozen=True)
class Spectrum:
    """One-sided amplitude spectrum.

    Attributes
    ----------
    omega : ndarray
        Angular frequency in rad/s.
    freq_hz : ndarray
        Frequency in Hz (``omega / 2 pi``).
    amplitude : ndarray
        Amplitude in the signal's units: a sinusoid ``A sin(w t)`` centred on a bin gives a
        peak of height A (Hann window, coherent-gain corrected).
    dt : float
        Sample spacing in s.
    """

    omega: np.ndarray
    freq_hz: np.ndarray
    amplitude: np.ndarray
    dt: float

    @property
    def d_omega(self) -> float:
        """Bin spacing in rad/s (``2 pi / (n_fft dt)``)."""
        return float(self.omega[1] - self.omega[0])


def amplitude_spectrum(
    x, dt: float, detrend: str = "constant", window: str = "hann", n_fft: int | None = None
) -> Spectrum:
    """Amplitude spectrum of a uniformly sampled signal.

    Why: identifies the frequencies present in x(t) (harmonics of the forcing, w1 and its
    combinations); the Hann window keeps leakage from strong lines from burying weak ones.

    Steps: remove the mean (or a linear trend), multiply by the window, ``rfft``, scale by
    ``2 / sum(window)`` (``1 / sum(window)`` for the DC and Nyquist bins).

    Parameters
    ----------
    x : array_like, shape (n,)
        Signal samples, finite, n >= 8 (e.g. displacement in m).
    dt : float
        Sample spacing in s.
    detrend : {"constant", "linear", "none"}, default "constant"
        "linear" removes slow drift of measured data, but on a short record it also leaks
        the projection of strong lines onto a ramp into the lowest bins.
    window : str, default "hann"
        Any window name accepted by ``scipy.signal.get_window`` ("boxcar" for none).
    n_fft : int, optional
        DFT length >= n (zero padding interpolates the spectrum); default n.

    Returns
    -------
    Spectrum
    """
    v = as_finite_1d(x, "x", min_size=8)
    dt = check_positive_scalar(dt, "dt")
    if detrend not in ("linear", "constant", "none"):
        raise ValueError(f"detrend must be 'linear', 'constant' or 'none', got {detrend!r}")
    n = v.size
    n_fft = n if n_fft is None else int(n_fft)
    if n_fft < n:
        raise ValueError(f"n_fft must be >= the number of samples ({n}), got {n_fft}")
    from scipy import signal

    if detrend != "none":
        v = signal.detrend(v, type=detrend)
    w = signal.get_window(window, n, fftbins=False)
    amp = np.abs(np.fft.rfft(v * w, n_fft)) * (2.0 / w.sum())
    amp[0] /= 2
    if n_fft % 2 == 0:
        amp[-1] /= 2
    f = np.fft.rfftfreq(n_fft, dt)
    return Spectrum(2 * np.pi * f, f, amp, dt)


@dataclass(frozen=True)
class SpectralPeaks:
    """Spectral peaks, strongest first.

    Attributes
    ----------
    omega : ndarray
        Refined peak angular frequencies (rad/s).
    freq_hz : ndarray
        The same in Hz.
    amplitude : ndarray
        Refined peak amplitudes (signal units).
    prominence_db : ndarray
        Prominence of each peak in dB of amplitude.
    """

    omega: np.ndarray
    freq_hz: np.ndarray
    amplitude: np.ndarray
    prominence_db: np.ndarray


def find_peaks_spectrum(
    spectrum: Spectrum,
    n_peaks: int | None = None,
    prominence_db: float = 10.0,
    dynamic_range_db: float = 80.0,
) -> SpectralPeaks:
    """Find the strongest spectral lines with sub-bin frequency refinement.

    Why: automatic, reproducible line frequencies for labelling Fig. 4c and for estimating
    w1, instead of reading them off a plot.

    Peaks are local maxima of ``20 log10(amplitude)`` (``scipy.signal.find_peaks``) with a
    prominence of at least ``prominence_db`` and a height within ``dynamic_range_db`` of
    the strongest line (this keeps round-off noise out); the DC bin is ignored.  Each peak
    is refined by a parabola through the log-amplitude of its bin and the two neighbours,
    which for a Hann window locates a pure tone to a few hundredths of a bin.

    Parameters
    ----------
    spectrum : Spectrum
        From :func:`amplitude_spectrum`.
    n_peaks : int, optional
        Keep only the strongest ``n_peaks``; default all that pass the thresholds.
    prominence_db : float, default 10
    dynamic_range_db : float, default 80

    Returns
    -------
    SpectralPeaks
    """
    if not isinstance(spectrum, Spectrum):
        raise ValueError("spectrum must be a Spectrum from amplitude_spectrum()")
    if prominence_db < 0 or dynamic_range_db <= 0:
        raise ValueError("prominence_db must be >= 0 and dynamic_range_db > 0")
    if n_peaks is not None and int(n_peaks) < 1:
        raise ValueError(f"n_peaks must be >= 1, got {n_peaks}")
    amp = spectrum.amplitude
    if not np.any(amp[1:] > 0):
        raise ValueError("spectrum is identically zero (constant signal?)")
    db = 20 * np.log10(np.maximum(amp, np.finfo(float).tiny))
    top = db[1:].max()
    from scipy import signal

    idx, props = signal.find_peaks(db, prominence=prominence_db, height=top - dynamic_range_db)
    keep = idx > 0
    idx, prom = idx[keep], props["prominences"][keep]
    order = np.argsort(amp[idx])[::-1]
    if n_peaks is not None:
        order = order[: int(n_peaks)]
    idx, prom = idx[order], prom[order]
    off, val_db = parabolic_refine(db, idx)
    d_omega = spectrum.d_omega
    omega = spectrum.omega[idx] + off * d_omega
    return SpectralPeaks(omega, omega / (2 * np.pi), 10 ** (val_db / 20), prom)


@dataclass(frozen=True)
class CombinationLabel:
    """A combination frequency ``k w + m w1`` and the spectral peak matched to it.

    Attributes
    ----------
    label : str
        E.g. "a".
    k, m : int
        Multiples of w and w1.
    expected : float
        ``k w + m w1`` in rad/s.
    found : float
        Matched peak frequency in rad/s, NaN if no peak within the tolerance.
    peak_index : int
        Index into the peak array, -1 if unmatched.
    """

    label: str
    k: int
    m: int
    expected: float
    found: float
    peak_index: int

    @property
    def matched(self) -> bool:
        return self.peak_index >= 0


def label_combinations(
    peaks_omega, omega: float, omega1: float, combos=None, tol: float | None = None
) -> tuple[CombinationLabel, ...]:
    """Match spectral peaks to combination frequencies ``k w + m w1``.

    Why: reproduces the a, b, c, d, f annotations of paper Fig. 4c from the peak list.

    Parameters
    ----------
    peaks_omega : array_like or SpectralPeaks
        Peak frequencies in rad/s.
    omega : float
        Forcing frequency w in rad/s.
    omega1 : float
        Secondary frequency w1 in rad/s.
    combos : dict of str -> (int, int), optional
        Label -> (k, m); default :data:`PAPER_COMBINATIONS`.
    tol : float, optional
        Absolute matching tolerance in rad/s; default ``0.01 * omega1``.  It should exceed
        the peak-frequency error (a fraction of the bin ``2 pi / record length``) times
        ``|k| + |m|``.

    Returns
    -------
    tuple of CombinationLabel
        In the order of ``combos``; each matched to the nearest peak within ``tol``.
    """
    p = peaks_omega.omega if isinstance(peaks_omega, SpectralPeaks) else peaks_omega
    p = as_finite_1d(p, "peaks_omega")
    omega = check_positive_scalar(omega, "omega")
    omega1 = check_positive_scalar(omega1, "omega1")
    combos = PAPER_COMBINATIONS if combos is None else dict(combos)
    tol = 0.01 * omega1 if tol is None else check_positive_scalar(tol, "tol")
    out = []
    for label, (k, m) in combos.items():
        expected = k * omega + m * omega1
        dist = np.abs(p - expected)
        j = int(np.argmin(dist))
        if dist[j] <= tol:
            out.append(CombinationLabel(label, int(k), int(m), expected, float(p[j]), j))
        else:
            out.append(CombinationLabel(label, int(k), int(m), expected, float("nan"), -1))
    return tuple(out)


@dataclass(frozen=True)
class SecondaryFrequency:
    """Estimated secondary frequency w1 and the evidence for it.

    Attributes
    ----------
    omega1 : float
        w1 in rad/s (the refined frequency of the chosen peak).
    amplitude : float
        Amplitude of that peak (signal units).
    labels : tuple of CombinationLabel
        The combinations checked, with their matches.
    """

    omega1: float
    amplitude: float
    labels: tuple

    @property
    def n_matched(self) -> int:
        """How many of the combinations were found among the peaks."""
        return sum(lab.matched for lab in self.labels)


def estimate_secondary_frequency(
    peaks: SpectralPeaks,
    omega: float,
    combos=None,
    tol: float | None = None,
    min_matched: int = 2,
) -> SecondaryFrequency:
    """Estimate w1 < w: the strongest non-harmonic peak below w confirmed by combinations.

    Why: the paper identifies the post-grazing regime as quasi-periodic with frequencies w
    and w1 from the spectrum; this makes the choice of w1 automatic.

    Candidates are peaks in ``(tol, w - tol)`` (so not at DC or a harmonic ``k w``), tried
    from the strongest down; the first for which at least ``min_matched`` of the
    combinations ``k w + m w1`` are present among the peaks is returned.  Note that the
    spectrum cannot distinguish w1 from w - w1 (both generate the same lines
    ``k w +/- w1``); this rule resolves the ambiguity in favour of the stronger line.

    Parameters
    ----------
    peaks : SpectralPeaks
        From :func:`find_peaks_spectrum`.
    omega : float
        Forcing frequency w in rad/s.
    combos : dict, optional
        Combinations used as evidence; default :data:`PAPER_COMBINATIONS`.
    tol : float, optional
        Frequency tolerance in rad/s for harmonics and combinations; default ``0.005 w``.
    min_matched : int, default 2

    Returns
    -------
    SecondaryFrequency

    Raises
    ------
    ValueError
        If no candidate is confirmed (e.g. a periodic signal with only harmonics).
    """
    if not isinstance(peaks, SpectralPeaks):
        raise ValueError("peaks must be a SpectralPeaks from find_peaks_spectrum()")
    omega = check_positive_scalar(omega, "omega")
    tol = 0.005 * omega if tol is None else check_positive_scalar(tol, "tol")
    if peaks.omega.size == 0:
        raise ValueError("no spectral peaks given")
    order = np.argsort(peaks.amplitude)[::-1]
    for j in order:
        w1 = float(peaks.omega[j])
        if not tol < w1 < omega - tol:
            continue
        labels = label_combinations(peaks.omega, omega, w1, combos, tol)
        if sum(lab.matched for lab in labels) >= min_matched:
            return SecondaryFrequency(w1, float(peaks.amplitude[j]), labels)
    raise ValueError(
        f"no secondary frequency below omega={omega} with at least {min_matched} "
        f"combination lines was found among {peaks.omega.size} peaks"
    )
