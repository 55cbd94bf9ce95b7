"""Autocorrelation of an interval sequence (paper eq. 3) and its Fourier spectrum (Fig. 10).

Lag convention: the paper's index k starts at 1 and means lag ``k - 1`` (so ACF(1) = 1).
Eq. (3) as printed pairs ``S_i`` with ``S_{i-k+1}``, a typo for ``S_{i+k-1}`` (DESIGN.md,
"Replication notes"); the paper's ``n / (n - k + 1)`` normalisation is kept:

    ACF(k) = n/(n-k+1) * sum_{i=1}^{n-k+1} (S_i - <S>)(S_{i+k-1} - <S>)
                       / sum_{i=1}^{n} (S_i - <S>)^2

With ``L = k - 1`` this is the lag-L sample autocovariance averaged over its ``n - L`` pairs
divided by the sample variance (both with the 1/count convention, i.e. ddof=0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import fft

from impactosc.statistics._peaks import parabolic_refine
from impactosc.statistics._validation import as_finite_1d

__all__ = ["Autocorrelation", "ACFSpectrum", "autocorrelation", "shuffled_autocorrelations", "acf_spectrum"]


@dataclass(frozen=True)
class Autocorrelation:
    """ACF of a sequence in the paper's indexing.

    Attributes
    ----------
    k : ndarray of int
        Paper index k = 1 .. kmax.
    value : ndarray
        ACF(k), dimensionless; ``value[0] == 1``.
    n : int
        Length of the sequence it was computed from.
    """

    k: np.ndarray
    value: np.ndarray
    n: int

    @property
    def lag(self) -> np.ndarray:
        """Index lag ``k - 1`` (in intervals)."""
        return self.k - 1


def autocorrelation(S, kmax: int | None = None) -> Autocorrelation:
    """Paper eq. (3) autocorrelation for k = 1 .. kmax (lag k - 1).

    Why: correlations between successive intervals reveal the hidden time scales of the
    chaotic train (paper Fig. 10, left).

    Parameters
    ----------
    S : array_like, shape (n,)
        Sequence (ISIs in s, penetrations in m; units cancel), n >= 2, not constant.
    kmax : int, optional
        Largest paper index, 1 <= kmax <= n.  Default ``n // 4`` (at least 1): beyond that
        few pairs remain and the n/(n-k+1) factor amplifies the noise.

    Returns
    -------
    Autocorrelation
    """
    s = as_finite_1d(S, "S", min_size=2)
    n = s.size
    if kmax is None:
        kmax = max(1, n // 4)
    kmax = int(kmax)
    if not 1 <= kmax <= n:
        raise ValueError(f"kmax must be between 1 and n={n}, got {kmax}")
    d = s - s.mean()
    denom = float(np.dot(d, d))
    _require_spread(denom, s)
    # sum_i d_i d_{i+L} for L = 0..kmax-1 (output index n-1 is lag 0); "auto" sums directly
    # for short series and uses the FFT (O(n log n)) for long ones.
    from scipy import signal

    raw = signal.correlate(d, d, mode="full", method="auto")[n - 1 : n - 1 + kmax]
    return Autocorrelation(np.arange(1, kmax + 1), _normalised(raw, n, denom), n)


def _require_spread(denom, s):
    """Raise for a constant sequence (sum d^2 below ~1e-28 sum s^2: relative spread ~1e-14)."""
    if np.any(np.asarray(denom) <= 1e-28 * float(np.dot(s, s))):
        raise ValueError("S is constant; its autocorrelation is undefined")


def _normalised(raw, n, denom):
    """Eq. (3) from the lag sums ``raw`` (lags 0.. along the last axis) and sum d^2."""
    lag = np.arange(raw.shape[-1])
    value = n / (n - lag) * raw / np.asarray(denom)[..., None]
    value[..., 0] = 1.0  # exact by definition; removes rounding
    return value


def shuffled_autocorrelations(S, kmax: int, n_shuffles: int, rng: np.random.Generator) -> np.ndarray:
    """ACF values (k = 1 .. kmax) of ``n_shuffles`` random permutations of S, shape (n_shuffles, kmax).

    Why: a significance level needs the ACFs of hundreds of shuffled copies; one FFT of all
    of them at once replaces hundreds of ``signal.correlate`` calls.  Row i is
    ``autocorrelation(rng.permutation(S), kmax).value`` of the i-th permutation drawn (same
    random stream) to rounding (a few 1e-16): the lag sums come from the power spectrum,
    zero-padded to at least n + kmax - 1 so no lag below kmax wraps around.
    """
    s = as_finite_1d(S, "S", min_size=2)
    n = s.size
    if not 1 <= kmax <= n:
        raise ValueError(f"kmax must be between 1 and n={n}, got {kmax}")
    rows = np.stack([rng.permutation(s) for _ in range(n_shuffles)]) if n_shuffles else np.empty((0, n))
    d = rows - rows.mean(axis=1, keepdims=True)
    denom = np.einsum("ij,ij->i", d, d)
    _require_spread(denom, s)
    nfft = fft.next_fast_len(n + kmax - 1, real=True)
    spec = fft.rfft(d, nfft, axis=1)
    raw = fft.irfft(spec.real**2 + spec.imag**2, nfft, axis=1)[:, :kmax]
    return _normalised(raw, n, denom)


@dataclass(frozen=True)
class ACFSpectrum:
    """Magnitude of the Fourier transform of an ACF, and its strongest peaks.

    Attributes
    ----------
    frequency : ndarray
        Frequency in cycles per interval index, 0 .. 0.5.
    magnitude : ndarray
        ``|sum_L ACF(L+1) exp(-2 pi i f L)| / n_lags`` (dimensionless).
    peak_frequency : ndarray
        Frequencies of the strongest peaks (cycles/index), strongest first, sub-bin refined.
    peak_magnitude : ndarray
        Magnitudes at those peaks.
    """

    frequency: np.ndarray
    magnitude: np.ndarray
    peak_frequency: np.ndarray
    peak_magnitude: np.ndarray

    @property
    def peak_period(self) -> np.ndarray:
        """Peak periods in intervals (``1 / peak_frequency``); multiply by mean ISI for s."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.peak_frequency


def acf_spectrum(
    acf,
    n_peaks: int = 2,
    min_prominence: float = 0.05,
    n_fft: int | None = None,
    include_zero: bool = False,
) -> ACFSpectrum:
    """Fourier transform of an ACF (paper Fig. 10, right) with automatic peak detection.

    Why: peaks of the ACF spectrum are periodicities of the interval sequence, measured
    in intervals (frequency in cycles per interval index); the paper reports two.

    The spectrum is the one-sided DFT magnitude of the ACF values (lags 0 .. kmax-1)
    divided by the number of lags.  Peaks are found with ``scipy.signal.find_peaks`` on the
    magnitude mirrored about f = 0 and f = 0.5, so a peak sitting exactly at the Nyquist
    frequency 0.5 (an alternating sequence) is found; only peaks with prominence at least
    ``min_prominence * max(magnitude)`` count.  Positions are refined by a parabola through
    the log-magnitude.

    Parameters
    ----------
    acf : Autocorrelation or array_like
        ACF values starting at lag 0 (``ACF(1) = 1``), at least 4 values.
    n_peaks : int, default 2
        How many of the strongest peaks to return (fewer if fewer exist).
    min_prominence : float, default 0.05
        Prominence threshold relative to the largest magnitude.
    n_fft : int, optional
        DFT length (zero padding); default the number of lags (no padding, no sidelobes
        from padding).
    include_zero : bool, default False
        Whether a peak at f = 0 (slow decay / trend, not a periodicity) may be reported.

    Returns
    -------
    ACFSpectrum
    """
    values = acf.value if isinstance(acf, Autocorrelation) else acf
    a = as_finite_1d(values, "acf", min_size=4)
    m = a.size
    n_fft = m if n_fft is None else int(n_fft)
    if n_fft < m:
        raise ValueError(f"n_fft must be >= the number of ACF values ({m}), got {n_fft}")
    if n_peaks < 1:
        raise ValueError(f"n_peaks must be >= 1, got {n_peaks}")
    mag = np.abs(np.fft.rfft(a, n_fft)) / m
    freq = np.fft.rfftfreq(n_fft)
    nb = mag.size
    # Mirror about f=0 and f=0.5 so edge maxima become interior peaks.  For even n_fft the
    # last bin is f=0.5 itself; for odd n_fft f=0.5 lies half a bin beyond it.
    right = mag[-2::-1] if n_fft % 2 == 0 else mag[::-1]
    ext = np.concatenate([mag[:0:-1], mag, right])
    from scipy import signal

    idx, _ = signal.find_peaks(ext, prominence=min_prominence * mag.max())
    idx = idx - (nb - 1)
    keep = (idx >= 0) & (idx < nb)
    if not include_zero:
        keep &= idx > 0
    idx = idx[keep]
    idx = idx[np.argsort(mag[idx])[::-1]][:n_peaks]
    logm = np.log(np.maximum(mag, np.finfo(float).tiny))
    off, logv = parabolic_refine(logm, idx)
    df = freq[1] - freq[0]
    pf = np.clip(freq[idx] + off * df, 0.0, 0.5)
    return ACFSpectrum(freq, mag, pf, np.exp(logv))
