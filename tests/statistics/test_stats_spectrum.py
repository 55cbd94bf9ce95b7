"""Amplitude spectrum, peak refinement, combination labels and w1 estimation."""

import numpy as np
import pytest

from impactosc.statistics import (
    PAPER_COMBINATIONS,
    amplitude_spectrum,
    estimate_secondary_frequency,
    find_peaks_spectrum,
    label_combinations,
)

DT = 0.005  # s (200 Hz)
T = np.arange(0.0, 100.0, DT)  # 100 s record, like the recorded span of the w=23.03 scene
D_OMEGA = 2 * np.pi / (T.size * DT)  # bin spacing 0.0628 rad/s
W = 23.03  # rad/s


@pytest.mark.parametrize("frac", [0.0, 0.13, 0.27, 0.41, 0.5])
def test_sinusoid_frequency_and_amplitude(frac):
    w0 = (300 + frac) * D_OMEGA  # about 18.9 rad/s, off-bin by `frac`
    x = 1e-3 * (1.3 * np.sin(w0 * T + 0.4)) + 2e-3  # m, with an offset removed by detrending
    spec = amplitude_spectrum(x, DT)
    assert spec.d_omega == pytest.approx(D_OMEGA)
    np.testing.assert_allclose(spec.freq_hz, spec.omega / (2 * np.pi))
    peaks = find_peaks_spectrum(spec)
    assert peaks.omega.size == 1  # Hann sidelobes decay monotonically: no spurious peaks
    # log-parabolic interpolation on a Hann window: bias < 0.02 bin (measured <= 0.016)
    assert abs(peaks.omega[0] - w0) < 0.05 * D_OMEGA
    assert peaks.freq_hz[0] == pytest.approx(peaks.omega[0] / (2 * np.pi))
    # residual scalloping after log-parabolic correction is < 4 % at half a bin
    assert peaks.amplitude[0] == pytest.approx(1.3e-3, rel=0.05)


def test_two_sinusoids_resolved():
    w_a, w_b = 10.0, 37.5
    x = np.sin(w_a * T) + 0.01 * np.sin(w_b * T)  # 40 dB apart
    peaks = find_peaks_spectrum(amplitude_spectrum(x, DT), n_peaks=2)
    np.testing.assert_allclose(peaks.omega, [w_a, w_b], atol=0.05 * D_OMEGA)
    np.testing.assert_allclose(peaks.amplitude, [1.0, 0.01], rtol=0.05)


def _quasi_periodic(w1):
    """Harmonics of W plus w1 and the Fig. 4c combinations, amplitudes decreasing."""
    lines = {
        (1, 0): 1.0,
        (2, 0): 0.3,
        (3, 0): 0.1,
        (0, 1): 0.5,
        (1, -1): 0.2,
        (1, 1): 0.15,
        (2, -1): 0.1,
        (2, 1): 0.08,
        (3, -1): 0.05,
    }
    phases = np.random.default_rng(0).uniform(0, 2 * np.pi, len(lines))
    return sum(a * np.sin((k * W + m * w1) * T + p) for ((k, m), a), p in zip(lines.items(), phases))


@pytest.mark.parametrize("w1", [W / 4, W * (np.sqrt(5) - 1) / 4], ids=["w/4", "irrational"])
def test_secondary_frequency_and_combination_labels(w1):
    peaks = find_peaks_spectrum(amplitude_spectrum(_quasi_periodic(w1), DT))
    assert peaks.omega.size == 9  # 3 harmonics + w1 + 5 combinations, nothing else
    est = estimate_secondary_frequency(peaks, W)
    # w1 is a peak frequency: refinement error plus neighbour leakage < 0.1 bin
    assert abs(est.omega1 - w1) < 0.1 * D_OMEGA
    assert est.n_matched == 5
    labels = label_combinations(peaks, W, est.omega1, tol=0.5 * D_OMEGA)
    assert [lab.label for lab in labels] == list(PAPER_COMBINATIONS)
    for lab in labels:
        k, m = PAPER_COMBINATIONS[lab.label]
        assert lab.matched
        assert (lab.k, lab.m) == (k, m)
        # matched peak is the synthetic line k W + m w1, to a fraction of a bin
        assert abs(lab.found - (k * W + m * w1)) < 0.2 * D_OMEGA


def test_periodic_signal_has_no_secondary_frequency():
    x = np.sin(W * T) + 0.3 * np.sin(2 * W * T + 1) + 0.1 * np.sin(3 * W * T)
    peaks = find_peaks_spectrum(amplitude_spectrum(x, DT))
    np.testing.assert_allclose(np.sort(peaks.omega), [W, 2 * W, 3 * W], atol=0.05 * D_OMEGA)
    with pytest.raises(ValueError, match="no secondary frequency"):
        estimate_secondary_frequency(peaks, W)


def test_unmatched_combination_is_reported():
    labels = label_combinations([W - 5.0, W + 5.0], W, 5.0, tol=0.01)
    assert [lab.matched for lab in labels] == [True, True, False, False, False]
    assert labels[0].peak_index == 0 and labels[1].peak_index == 1
    assert np.isnan(labels[2].found) and labels[2].peak_index == -1
