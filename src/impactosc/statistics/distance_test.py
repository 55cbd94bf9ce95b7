"""Whether two trains are closer in time than chance: their distances against surrogates.

Why: the ISI- and SPIKE-distances of two trains (:mod:`impactosc.statistics.train_distances`)
have no scale of their own; chance gives the scale. The test, for each distance and each
surrogate kind (:mod:`impactosc.statistics.train_surrogates`):

* null hypothesis: the trains share no timing (neither carries information about when the
  other's events fall, beyond what the surrogate keeps of each train's own structure);
* statistic: the distance D between the two trains on their common span;
* null sample: D between a surrogate of the first train and the second train, and between the
  first train and a surrogate of the second, ``n_surrogates`` of each (2 n_surrogates values);
* p-value, one-sided (a small distance is evidence of shared timing):
  ``p = (1 + #{null values <= D}) / (1 + 2 n_surrogates)``, the Monte Carlo p-value that never
  reads 0 (Davison & Hinkley 1997). Its false-positive rate on independent trains of one
  process is checked in tests/statistics/test_stats_distance_test.py (slow).

A large distance is not tested: two independent trains' distance depends on both processes,
and a difference of processes shows in the statistics side by side (C_V^2, CV2, LV, ...).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics.train_distances import isi_distance, spike_distance
from impactosc.statistics.train_surrogates import SURROGATE_KINDS, surrogate

__all__ = ["DISTANCES", "DistanceTest", "distance_tests"]

#: The distances, by the name the command line and the statistics files use.
DISTANCES = {"isi_distance": isi_distance, "spike_distance": spike_distance}


@dataclass(frozen=True)
class DistanceTest:
    """One distance between two trains and its surrogate test.

    Attributes
    ----------
    distance : str
        ``isi_distance`` or ``spike_distance``.
    surrogates : str
        The surrogate kind (``joint_isi`` or ``shuffled``).
    value : float
        The distance between the two trains (dimensionless, 0 = identical).
    null : ndarray
        The distances of the null sample (2 n_surrogates values).
    pvalue : float
        ``(1 + #{null <= value}) / (1 + null.size)``.
    """

    distance: str
    surrogates: str
    value: float
    null: np.ndarray
    pvalue: float

    def summary(self) -> dict:
        """The JSON-ready numbers: value, p-value, and the null sample's mean, sd and 5 % quantile."""
        return {
            "value": self.value,
            "pvalue": self.pvalue,
            "null_mean": float(self.null.mean()),
            "null_sd": float(self.null.std(ddof=1)),
            "null_q05": float(np.quantile(self.null, 0.05)),
            "n_null": int(self.null.size),
        }


def distance_tests(
    times1,
    times2,
    t_start: float,
    t_stop: float,
    n_surrogates: int = 99,
    kinds=SURROGATE_KINDS,
    seed: int = 0,
) -> list[DistanceTest]:
    """Both distances of two trains on [t_start, t_stop] (s), each tested against each surrogate kind.

    Both trains must lie inside the span with at least 4 events each (joint-ISI dithering
    moves the inner events). One generator (``seed``) draws every surrogate, so a result is
    reproducible; the same surrogates serve both distances.
    """
    n = int(n_surrogates)
    if n < 1:
        raise ValueError(f"n_surrogates must be >= 1, got {n_surrogates}")
    rng = np.random.default_rng(seed)
    pairs = {name: f(times1, times2, t_start, t_stop) for name, f in DISTANCES.items()}
    out = []
    for kind in kinds:
        null = {name: [] for name in DISTANCES}
        for _ in range(n):
            sur1 = surrogate(kind, times1, rng)
            sur2 = surrogate(kind, times2, rng)
            for name, f in DISTANCES.items():
                null[name].append(f(sur1, times2, t_start, t_stop))
                null[name].append(f(times1, sur2, t_start, t_stop))
        for name, value in pairs.items():
            sample = np.asarray(null[name])
            p = (1 + np.count_nonzero(sample <= value)) / (1 + sample.size)
            out.append(DistanceTest(name, kind, float(value), sample, float(p)))
    return out
