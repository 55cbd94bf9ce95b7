"""Statistics of impact trains, for simulated and measured data alike.

Inputs are plain numpy arrays: impact onset times ``T_j`` (s, strictly increasing),
inter-impact intervals ``S_j = T_{j+1} - T_j`` (s), penetrations ``H_j`` (m), or a uniformly
sampled signal x(t).  All functions are pure and raise ``ValueError`` naming the problem
for empty, non-finite, unsorted or too-short input.

Modules
-------
intervals    ISIs, return maps, distinct levels of a periodic train (Figs 3, 5, 7b)
counts       counts in windows and the equal-rate (stationarity) test (Sec. 2.2)
variability  running C_V^2 (paper's dimensionful and the dimensionless one), Fano factor (Fig. 8)
acf          paper eq. (3) autocorrelation (lag k-1) and its spectrum (Fig. 10)
density      relative-frequency histogram, kernel density, density maxima (Figs 9, 11)
mixture      1-/2-component gaussian/lognormal/gamma mixtures, BIC ranking
poisson      KS test of the ISIs against the exponential law
spectrum     amplitude spectrum, peaks, combination-frequency labels (Figs 4c, 6b)

scipy.signal and scipy.stats are imported inside the functions that call them: importing them
costs 1-2 s, which every workflow job importing this package would pay, most of them for nothing.
"""

from impactosc.statistics.acf import (
    ACFSpectrum,
    Autocorrelation,
    acf_spectrum,
    autocorrelation,
    shuffled_autocorrelations,
)
from impactosc.statistics.counts import EqualRateTest, counts_in_windows, equal_rate_test, window_counts
from impactosc.statistics.density import (
    DensityMaxima,
    Histogram,
    KernelDensity,
    density_maxima,
    kernel_density,
    relative_frequency_histogram,
)
from impactosc.statistics.intervals import DistinctLevels, distinct_levels, inter_impact_intervals, return_map
from impactosc.statistics.mixture import FAMILIES, MixtureFit, MixtureSelection, fit_mixture, select_mixture
from impactosc.statistics.poisson import ExponentialKSTest, exponential_ks_test
from impactosc.statistics.spectrum import (
    PAPER_COMBINATIONS,
    CombinationLabel,
    SecondaryFrequency,
    SpectralPeaks,
    Spectrum,
    amplitude_spectrum,
    estimate_secondary_frequency,
    find_peaks_spectrum,
    label_combinations,
)
from impactosc.statistics.variability import (
    FanoCurve,
    RunningStatistic,
    cv2_paper_running,
    cv2_running,
    fano_curve,
    fano_factor,
)

__all__ = [
    # intervals
    "DistinctLevels",
    "inter_impact_intervals",
    "return_map",
    "distinct_levels",
    # counts
    "EqualRateTest",
    "counts_in_windows",
    "window_counts",
    "equal_rate_test",
    # variability
    "RunningStatistic",
    "FanoCurve",
    "cv2_paper_running",
    "cv2_running",
    "fano_factor",
    "fano_curve",
    # acf
    "Autocorrelation",
    "ACFSpectrum",
    "autocorrelation",
    "shuffled_autocorrelations",
    "acf_spectrum",
    # density
    "Histogram",
    "KernelDensity",
    "DensityMaxima",
    "relative_frequency_histogram",
    "kernel_density",
    "density_maxima",
    # mixture
    "FAMILIES",
    "MixtureFit",
    "MixtureSelection",
    "fit_mixture",
    "select_mixture",
    # poisson
    "ExponentialKSTest",
    "exponential_ks_test",
    # spectrum
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
