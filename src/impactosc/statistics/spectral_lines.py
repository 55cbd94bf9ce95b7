"""Spectra of a displacement record x(t): the lines the paper reads off Figs 4c and 6b.

Why together: both figures take the amplitude spectrum of a uniformly sampled x(t)
(:mod:`impactosc.statistics.spectrum`) and name its lines against the forcing frequency w:
Fig 4c (periodic regime) the secondary frequency w1 and its combinations k w +/- w1
(:func:`analyse_spectrum`), Fig 6b (chaos) one dominant line at w over a dense
low-frequency part (:func:`trajectory_spectrum`). Units: s, m, rad/s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from impactosc.statistics import amplitude_spectrum, estimate_secondary_frequency, find_peaks_spectrum
from impactosc.statistics._validation import as_event_times

__all__ = ["SpectrumAnalysis", "analyse_spectrum", "trajectory_spectrum"]


@dataclass(frozen=True)
class SpectrumAnalysis:
    """Spectrum of x(t) with its lines, w1 and the paper's combination labels (Fig. 4c).

    omega_axis, amplitude: the spectrum up to max_omega (rad/s, m); peaks_omega,
    peaks_amplitude: the lines; omega1: the secondary frequency (NaN if none) and
    ratio = omega1 / w with its nearest fraction p/q (q <= max_denominator); labels: label ->
    (expected, found) rad/s; harmonics_only: every line is within tol of a multiple of w.
    """

    omega: float
    omega_axis: np.ndarray
    amplitude: np.ndarray
    peaks_omega: np.ndarray
    peaks_amplitude: np.ndarray
    omega1: float
    ratio: float
    ratio_fraction: tuple
    labels: dict
    harmonics_only: bool
    resolution: float

    def to_dict(self) -> dict:
        return {
            "omega": self.omega,
            "omega1": self.omega1,
            "omega1_over_omega": self.ratio,
            "omega1_over_omega_fraction": list(self.ratio_fraction),
            "labels": self.labels,
            "harmonics_only": self.harmonics_only,
            "resolution": self.resolution,
            "peaks_omega": self.peaks_omega.tolist(),
            "peaks_amplitude": self.peaks_amplitude.tolist(),
            "omega_axis": self.omega_axis.tolist(),
            "amplitude": self.amplitude.tolist(),
        }


def analyse_spectrum(
    x,
    dt: float,
    omega: float,
    max_omega: float = 80.0,
    prominence_db: float = 10.0,
    dynamic_range_db: float = 60.0,
    max_denominator: int = 12,
) -> SpectrumAnalysis:
    """Lines of the spectrum of x(t) up to max_omega, w1 and the a, b, c, d, f combinations.

    Why: Fig. 4c. The peak finder keeps lines within `dynamic_range_db` of the strongest
    (60 dB keeps the labelled combinations and drops the Hann-window leakage floor); w1
    is the strongest non-harmonic line below w confirmed by the combinations
    (:func:`impactosc.statistics.estimate_secondary_frequency`). A line counts as a harmonic
    when it is within 1.5 bins of k w.
    """
    sp = amplitude_spectrum(x, dt)
    keep = sp.omega <= max_omega
    peaks = find_peaks_spectrum(sp, prominence_db=prominence_db, dynamic_range_db=dynamic_range_db)
    sel = peaks.omega <= max_omega
    p_om, p_amp = peaks.omega[sel], peaks.amplitude[sel]
    order = np.argsort(p_om)
    p_om, p_amp = p_om[order], p_amp[order]
    tol = 1.5 * sp.d_omega
    k = np.rint(p_om / omega)
    harmonics_only = bool(np.all((k >= 1) & (np.abs(p_om - k * omega) <= tol)))
    omega1, ratio, frac, labels = math.nan, math.nan, (0, 0), {}
    if not harmonics_only:
        sec = estimate_secondary_frequency(peaks, omega, tol=tol)
        omega1 = sec.omega1
        ratio = omega1 / omega
        f = Fraction(ratio).limit_denominator(max_denominator)
        frac = (f.numerator, f.denominator)
        labels = {
            lab.label: {"k": lab.k, "m": lab.m, "expected": lab.expected, "found": lab.found} for lab in sec.labels
        }
    return SpectrumAnalysis(
        float(omega),
        sp.omega[keep],
        sp.amplitude[keep],
        p_om,
        p_amp,
        float(omega1),
        float(ratio),
        frac,
        labels,
        harmonics_only,
        float(sp.d_omega),
    )


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
    spec = amplitude_spectrum(x, float(dt[0]))
    peaks = find_peaks_spectrum(spec, n_peaks=n_peaks)
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
