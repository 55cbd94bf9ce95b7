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
impact_train an impact train and the options of its analysis
train_analysis  every statistic of one train at once (analyse_train: Figs 6-11, any source)
periods      period of a Poincare sequence, impacts per orbit
periodic_train  the periodic regime's numbers (Figs 3a, 4, 5)
spectral_lines  the lines of a displacement spectrum (Figs 4c, 6b)
ensemble     the ensemble of realisations of a chaotic train and the spread of its numbers
local_variability  beyond the paper: Holt's CV2, LV, LvR, serial correlations of the intervals
train_distances    ISI- and SPIKE-distance of two trains (Kreuz et al. 2007, 2013; PySpike's edges)
train_surrogates   shuffled-interval and joint-ISI surrogates of a train
distance_test      the two distances of two trains against surrogates of each (p-values)
multiple_testing   two-sided p-values of z-scores and Holm's step-down for verdicts that test many

scipy.signal and scipy.stats are imported inside the functions that call them: importing them
costs 1-2 s, which every workflow job importing this package would pay, most of them for nothing.
"""

from impactosc._lazy import export

export(
    globals(),
    {
        "DistinctLevels": "impactosc.statistics.intervals",
        "inter_impact_intervals": "impactosc.statistics.intervals",
        "return_map": "impactosc.statistics.intervals",
        "distinct_levels": "impactosc.statistics.intervals",
        "EqualRateTest": "impactosc.statistics.counts",
        "counts_in_windows": "impactosc.statistics.counts",
        "window_counts": "impactosc.statistics.counts",
        "equal_rate_test": "impactosc.statistics.counts",
        "RunningStatistic": "impactosc.statistics.variability",
        "FanoCurve": "impactosc.statistics.variability",
        "cv2_paper_running": "impactosc.statistics.variability",
        "cv2_running": "impactosc.statistics.variability",
        "fano_factor": "impactosc.statistics.variability",
        "fano_curve": "impactosc.statistics.variability",
        "Autocorrelation": "impactosc.statistics.acf",
        "ACFSpectrum": "impactosc.statistics.acf",
        "autocorrelation": "impactosc.statistics.acf",
        "shuffled_autocorrelations": "impactosc.statistics.acf",
        "acf_spectrum": "impactosc.statistics.acf",
        "Histogram": "impactosc.statistics.density",
        "KernelDensity": "impactosc.statistics.density",
        "DensityMaxima": "impactosc.statistics.density",
        "relative_frequency_histogram": "impactosc.statistics.density",
        "kernel_density": "impactosc.statistics.density",
        "density_maxima": "impactosc.statistics.density",
        "FAMILIES": "impactosc.statistics.mixture",
        "MixtureFit": "impactosc.statistics.mixture",
        "MixtureSelection": "impactosc.statistics.mixture",
        "fit_mixture": "impactosc.statistics.mixture",
        "select_mixture": "impactosc.statistics.mixture",
        "ExponentialKSTest": "impactosc.statistics.poisson",
        "exponential_ks_test": "impactosc.statistics.poisson",
        "PAPER_COMBINATIONS": "impactosc.statistics.spectrum",
        "Spectrum": "impactosc.statistics.spectrum",
        "SpectralPeaks": "impactosc.statistics.spectrum",
        "CombinationLabel": "impactosc.statistics.spectrum",
        "SecondaryFrequency": "impactosc.statistics.spectrum",
        "amplitude_spectrum": "impactosc.statistics.spectrum",
        "find_peaks_spectrum": "impactosc.statistics.spectrum",
        "label_combinations": "impactosc.statistics.spectrum",
        "estimate_secondary_frequency": "impactosc.statistics.spectrum",
        "ImpactTrain": "impactosc.statistics.impact_train",
        "AnalysisOptions": "impactosc.statistics.impact_train",
        "load_train": "impactosc.statistics.impact_train",
        "analyse_train": "impactosc.statistics.train_analysis",
        "DEFAULT_REFRACTORINESS": "impactosc.statistics.local_variability",
        "holt_cv2": "impactosc.statistics.local_variability",
        "local_variation": "impactosc.statistics.local_variability",
        "revised_local_variation": "impactosc.statistics.local_variability",
        "serial_correlation": "impactosc.statistics.local_variability",
        "isi_distance": "impactosc.statistics.train_distances",
        "spike_distance": "impactosc.statistics.train_distances",
        "SURROGATE_KINDS": "impactosc.statistics.train_surrogates",
        "shuffled_isi_surrogate": "impactosc.statistics.train_surrogates",
        "joint_isi_surrogate": "impactosc.statistics.train_surrogates",
        "DISTANCES": "impactosc.statistics.distance_test",
        "DistanceTest": "impactosc.statistics.distance_test",
        "distance_tests": "impactosc.statistics.distance_test",
        "THREE_SD_LEVEL": "impactosc.statistics.multiple_testing",
        "HolmVerdict": "impactosc.statistics.multiple_testing",
        "two_sided_p": "impactosc.statistics.multiple_testing",
        "holm": "impactosc.statistics.multiple_testing",
        "largest_z_bound": "impactosc.statistics.multiple_testing",
    },
)
