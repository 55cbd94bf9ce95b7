"""The ISI-distance and the SPIKE-distance between two trains (Kreuz et al. 2007, 2013).

Why: a rig's train and the model's (or two models', or two rates') are compared impact by
impact, not only through summary statistics. Both distances are time averages of a profile
that compares the trains locally, 0 for identical trains:

* ISI-distance: ``I(t) = |nu_1(t) - nu_2(t)| / max(nu_1(t), nu_2(t))``, nu_n(t) the interval of
  train n that contains t (a rate-like comparison, blind to where inside the interval a spike falls);
* SPIKE-distance: each spike's distance to the nearest spike of the other train, interpolated
  between a train's previous and following spike and weighted by the local intervals (Kreuz et
  al. 2013, eq. 2-5), so it sees spike timing.

The edges follow PySpike (Mulansky & Kreuz 2016), against which the tests check these
functions: before the first spike and after the last, a train's interval is the longer of the
gap to the span's edge and its first (last) interval, as if an auxiliary spike stood there; an
auxiliary spike takes the nearest-spike distance of its neighbour. Both profiles are piecewise
constant or linear, so the averages are exact sums over the merged spike times (no sampling).
"""

from __future__ import annotations

import numpy as np

from impactosc.statistics._validation import as_event_times, check_time_span

__all__ = ["isi_distance", "spike_distance"]


def _train(times, name: str, t_start: float, t_stop: float) -> np.ndarray:
    t = as_event_times(times, name, min_size=2)
    if t[0] < t_start or t[-1] > t_stop:
        raise ValueError(f"{name} has spikes outside the span [{t_start}, {t_stop}] s: [{t[0]}, {t[-1]}]")
    return t


def _with_edges(t: np.ndarray, t_start: float, t_stop: float) -> np.ndarray:
    """The train with its auxiliary spikes: one interval before the first spike (or the span's
    start if that is earlier) and one after the last (or the span's end if that is later)."""
    first = min(t_start, t[0] - (t[1] - t[0]))
    last = max(t_stop, t[-1] + (t[-1] - t[-2]))
    return np.concatenate([[first], t, [last]])


def _pieces(t1, t2, t_start, t_stop):
    """The merged spike times with the span's ends (the pieces' edges), and each piece's midpoint,
    which locates the piece between two spikes of each train."""
    b = np.unique(np.concatenate([[t_start, t_stop], t1, t2]))
    mid = 0.5 * (b[:-1] + b[1:])
    return b, mid


def isi_distance(times1, times2, t_start: float, t_stop: float) -> float:
    """ISI-distance of two trains on the span [t_start, t_stop] (s), in [0, 1).

    Why: compares the trains' local intervals at every instant, so two trains with the same
    interval distribution but different ordering or rate profile differ (Kreuz et al. 2007).
    Each train needs at least 2 spikes inside the span.
    """
    a, b_ = check_time_span(t_start, t_stop)
    t1 = _train(times1, "times1", a, b_)
    t2 = _train(times2, "times2", a, b_)
    b, mid = _pieces(t1, t2, a, b_)
    nu = []
    for t in (t1, t2):
        e = _with_edges(t, a, b_)
        i = np.searchsorted(e, mid, side="right") - 1
        nu.append(e[i + 1] - e[i])
    profile = np.abs(nu[0] - nu[1]) / np.maximum(nu[0], nu[1])
    return float(np.sum(profile * np.diff(b)) / (b_ - a))


def _nearest_distance(t: np.ndarray, other: np.ndarray) -> np.ndarray:
    """Distance from each of ``t`` to the nearest element of the sorted ``other``."""
    j = np.clip(np.searchsorted(other, t), 1, other.size - 1)
    return np.minimum(np.abs(t - other[j - 1]), np.abs(other[j] - t))


def spike_distance(times1, times2, t_start: float, t_stop: float) -> float:
    """SPIKE-distance of two trains on the span [t_start, t_stop] (s), in [0, 1].

    Why: sensitive to spike timing, scaled by the local intervals, so it is comparable across
    rates (Kreuz et al. 2013). Each train needs at least 2 spikes inside the span.
    """
    a, b_ = check_time_span(t_start, t_stop)
    t1 = _train(times1, "times1", a, b_)
    t2 = _train(times2, "times2", a, b_)
    b, mid = _pieces(t1, t2, a, b_)
    edged = [_with_edges(t, a, b_) for t in (t1, t2)]
    local = []  # per train: S_n at the left and right end of each piece, and its interval
    for n, t in enumerate((t1, t2)):
        e = edged[n]
        d = _nearest_distance(t, edged[1 - n])
        d = np.concatenate([[d[0]], d, [d[-1]]])  # an auxiliary spike takes its neighbour's distance
        i = np.searchsorted(e, mid, side="right") - 1
        prev, follow = e[i], e[i + 1]
        isi = follow - prev

        def s_at(x, i=i, prev=prev, follow=follow, isi=isi, d=d):
            return (d[i] * (follow - x) + d[i + 1] * (x - prev)) / isi

        local.append((s_at(b[:-1]), s_at(b[1:]), isi))
    (s1l, s1r, isi1), (s2l, s2r, isi2) = local
    mean_isi = 0.5 * (isi1 + isi2)

    def profile(s1, s2):
        return 0.5 * (s1 * isi2 + s2 * isi1) / mean_isi**2

    left, right = profile(s1l, s2l), profile(s1r, s2r)
    return float(np.sum(0.5 * (left + right) * np.diff(b)) / (b_ - a))
