"""Bad input raises ValueError with a message that names the problem."""

import numpy as np
import pytest

import impactosc.statistics as st

NAN = float("nan")
GOOD_S = np.linspace(0.1, 0.3, 50)

CASES = [
    (st.inter_impact_intervals, ([],), "times is empty"),
    (st.inter_impact_intervals, ([1.0],), "too few samples"),
    (st.inter_impact_intervals, ([0.0, NAN, 2.0],), "non-finite"),
    (st.inter_impact_intervals, ([0.0, 2.0, 1.0],), "strictly increasing"),
    (st.inter_impact_intervals, ([0.0, 1.0, 1.0],), "strictly increasing"),
    (st.inter_impact_intervals, (np.ones((2, 2)),), "one-dimensional"),
    (st.return_map, ([1.0, 2.0], 0), "lag must be >= 1"),
    (st.distinct_levels, ([np.inf],), "non-finite"),
    (st.window_counts, ([1.0, 2.0], 5.0, 1.0, 3), "t_stop must be greater"),
    (st.window_counts, ([1.0, 2.0], 0.0, 5.0, 0), "n_windows must be >= 1"),
    (st.equal_rate_test, ([5],), "too few samples"),
    (st.equal_rate_test, ([5, -1, 3],), "non-negative integers"),
    (st.equal_rate_test, ([0, 0, 0],), "all zero"),
    (st.cv2_running, ([0.1, -0.2, 0.3],), "strictly positive"),
    (st.cv2_paper_running, ([0.1],), "too few samples"),
    (st.fano_factor, ([1.0, 2.0], 0.0, 0.0, 10.0), "window must be finite and positive"),
    (st.fano_factor, ([1.0, 2.0], 6.0, 0.0, 10.0), "fewer than 2 windows"),
    (st.fano_factor, ([11.0, 12.0], 1.0, 0.0, 10.0), "no events"),
    (st.autocorrelation, (np.full(10, 0.2),), "constant"),
    (st.autocorrelation, (GOOD_S, 51), "kmax must be between"),
    (st.acf_spectrum, ([1.0, 0.5],), "too few samples"),
    (st.kernel_density, ([0.2, 0.2, 0.2],), "all equal"),
    (st.density_maxima, ([0.0, 1.0, 2.0, 3.0], [1.0, 2.0, 1.0]), "same length"),
    (st.density_maxima, ([0.0, 1.0, 3.0], [1.0, 2.0, 1.0]), "evenly spaced"),
    (st.fit_mixture, (GOOD_S, "weibull"), "family must be one of"),
    (st.fit_mixture, (GOOD_S - 0.2, "gamma"), "strictly positive"),
    (st.fit_mixture, (GOOD_S[:5], "gamma", 2), "too few samples"),
    (st.exponential_ks_test, ([0.1, 0.2, NAN, 0.3, 0.4],), "non-finite"),
    (st.exponential_ks_test, ([0.1, 0.2],), "too few samples"),
    (st.amplitude_spectrum, (np.ones(16), 0.0), "dt must be finite and positive"),
    (st.amplitude_spectrum, (np.ones(4), 0.1), "too few samples"),
    (st.label_combinations, ([], 23.0, 5.0), "peaks_omega is empty"),
]


@pytest.mark.parametrize("func, args, message", CASES, ids=[f"{c[0].__name__}-{i}" for i, c in enumerate(CASES)])
def test_bad_input_raises_value_error(func, args, message):
    with pytest.raises(ValueError, match=message):
        func(*args)


def test_error_message_names_argument_and_index():
    msg = r"times must be strictly increasing; first violation at index 1"
    with pytest.raises(ValueError, match=msg):
        st.inter_impact_intervals([0.0, 2.0, 1.0])
    with pytest.raises(ValueError, match=r"S contains non-finite values .* index 2"):
        st.cv2_running([0.1, 0.2, NAN])
