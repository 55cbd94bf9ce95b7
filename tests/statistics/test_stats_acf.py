"""Paper eq. (3) autocorrelation (intended lag k-1) and its Fourier spectrum."""

import numpy as np
import pytest

from impactosc.statistics import acf_spectrum, autocorrelation, inter_impact_intervals


def _acf_direct(s, kmax):
    """Eq. (3) with the intended index S_{i+k-1}, written as loops over the paper's indices."""
    n = len(s)
    m = sum(s) / n
    den = sum((x - m) ** 2 for x in s)
    out = []
    for k in range(1, kmax + 1):
        num = sum((s[i - 1] - m) * (s[i + k - 2] - m) for i in range(1, n - k + 2))
        out.append(n / (n - k + 1) * num / den)
    return np.array(out)


def test_acf_matches_eq3_and_starts_at_one():
    s = np.random.default_rng(5).gamma(2.0, 0.07, 101)
    acf = autocorrelation(s, kmax=101)
    assert acf.value[0] == 1.0  # ACF(1) = 1: lag 0
    np.testing.assert_array_equal(acf.k[:3], [1, 2, 3])
    np.testing.assert_array_equal(acf.lag[:3], [0, 1, 2])
    # FFT vs direct sums: rounding only (the n/(n-k+1) factor reaches 101 at k=n)
    np.testing.assert_allclose(acf.value, _acf_direct(list(s), 101), rtol=0, atol=1e-11)


def test_acf_of_iid_sequence_is_small():
    n = 5000
    s = np.random.default_rng(9).exponential(0.14, n)
    acf = autocorrelation(s, kmax=21)
    # white noise: ACF(k>1) ~ N(0, 1/n); 20 values, 4 SE bound is essentially never hit
    assert np.all(np.abs(acf.value[1:]) < 4 / np.sqrt(n))


def test_acf_of_ar1_decays_geometrically():
    phi, n = 0.6, 20000
    rng = np.random.default_rng(1)
    e = rng.normal(size=n)
    s = np.empty(n)
    s[0] = e[0]
    for i in range(1, n):
        s[i] = phi * s[i - 1] + e[i]
    acf = autocorrelation(s + 10.0, kmax=8)
    # Bartlett SE for AR(1): sqrt((1+phi^2)/(1-phi^2)/n) = 0.0103; allow 4 SE
    se = np.sqrt((1 + phi**2) / (1 - phi**2) / n)
    np.testing.assert_allclose(acf.value, phi ** np.arange(8), atol=4 * se)


def test_alternating_sequence_has_peak_at_half_cycle_per_index():
    s = np.tile([0.1, 0.2], 200)
    acf = autocorrelation(s, kmax=100)
    # exactly alternating: ACF(k) = (-1)^(k-1) by construction of the n/(n-k+1) factor
    np.testing.assert_allclose(acf.value, (-1.0) ** np.arange(100), atol=1e-12)
    spec = acf_spectrum(acf)
    assert spec.peak_frequency.size == 1  # a single line, no other peak
    assert spec.peak_frequency[0] == pytest.approx(0.5, abs=1e-12)
    assert spec.peak_period[0] == pytest.approx(2.0)


def test_period4_sequence_has_peaks_at_quarter_and_half(period4_times):
    s = inter_impact_intervals(period4_times)
    spec = acf_spectrum(autocorrelation(s, kmax=120))
    # levels (0.1, 0.25, 0.18, 0.2884) have Fourier components at 1/4 and 1/2 cycle/index;
    # the 1/2 component (|0.1-0.25+0.18-0.2884|) dominates the 1/4 one.  120 lags is a
    # multiple of 4, so both lie on bins (jitter 1e-7 s moves them by << 1e-3).
    np.testing.assert_allclose(spec.peak_frequency, [0.5, 0.25], atol=1e-3)
    assert spec.peak_magnitude[0] > spec.peak_magnitude[1]


def _acf_old_fft(s, kmax):
    """The hand-written power-of-two FFT this replaced (commit 29f74da)."""
    n = s.size
    d = s - s.mean()
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    spec = np.fft.rfft(d, nfft)
    raw = np.fft.irfft(spec * np.conj(spec), nfft)[:kmax]
    lag = np.arange(kmax)
    value = n / (n - lag) * raw / np.dot(d, d)
    value[0] = 1.0
    return value


@pytest.mark.parametrize("n, kmax", [(2, 2), (101, 101), (400, 100), (7076, None), (20000, 8), (20000, None)])
def test_acf_matches_old_fft(n, kmax):
    # short series: signal.correlate's "auto" sums directly; long ones (7076, 20000): FFT
    rng = np.random.default_rng(n)
    s = 10.0 + np.convolve(rng.normal(size=n + 3), [1.0, 0.6, 0.3, 0.1], mode="valid")
    acf = autocorrelation(s, kmax=kmax)
    old = _acf_old_fft(s, acf.k.size)
    # both are sums of products normalised by sum d^2 (ACF(1) = 1): rounding ~ eps, then
    # scaled by n/(n-L) (up to n at the last lag); measured <= 2.3e-16 n/(n-L), allow 1e-12
    np.testing.assert_array_less(np.abs(acf.value - old), 1e-12 * n / (n - acf.lag))


@pytest.mark.parametrize("n", [59, 400, 4038])
def test_shuffled_acfs_are_the_acfs_of_the_same_permutations(n):
    """The batched FFT of the significance level gives, row by row, autocorrelation() of the
    permutations drawn from the same random stream (to rounding: ACF(1) = 1 sets the scale)."""
    from impactosc.statistics import shuffled_autocorrelations

    s = np.random.default_rng(n).gamma(2.0, 0.07, n)
    kmax = min(50, n)
    batched = shuffled_autocorrelations(s, kmax, 25, np.random.default_rng(0))
    rng = np.random.default_rng(0)
    one_by_one = np.stack([autocorrelation(rng.permutation(s), kmax=kmax).value for _ in range(25)])
    assert batched.shape == (25, kmax)
    np.testing.assert_allclose(batched, one_by_one, rtol=0, atol=1e-13)
