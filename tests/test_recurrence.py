"""Attractors found by recurrence, their fractions and basin entropy, on maps whose attractors
and basins are known exactly (impactosc.dynamics.recurrence, impactosc.dynamics.basin_mixing)."""

import math

import numpy as np
import pytest

from impactosc.dynamics.basin_mixing import basin_entropy, grid_boxes, sample_boxes
from impactosc.dynamics.basins import basin_fractions
from impactosc.dynamics.recurrence import CHAOTIC_EXPONENT, UNRESOLVED, RecurrenceSettings, discover


class _Map:
    """A map of (x, y) given by step(x, y) and its Jacobian; the largest exponent by QR of the
    exact Jacobians (the discovery only reads it)."""

    def iterate(self, state, n):
        x, y = float(state[0]), float(state[1])
        out = np.empty((n, 2))
        for k in range(n):
            x, y = self.step(x, y)
            out[k] = x, y
        return out, out[-1].copy()

    def describe(self, point, period):
        x, y = float(point[0]), float(point[1])
        q, total, n = np.array([1.0, 1.0]) / math.sqrt(2), 0.0, 400
        for _ in range(n):
            q = self.jacobian(x, y) @ q
            g = np.linalg.norm(q)
            total, q = total + math.log(g), q / g
            x, y = self.step(x, y)
        return 0.0, total / n


class TwoWells(_Map):
    """x -> x - 0.3 sin(2 pi x) / (2 pi), y -> y / 2: stable fixed points (0, 0) and (1, 0)
    (x' = 0.7), unstable x = 1/2 (x' = 1.3); x' > 0 everywhere, so the basin of (0, 0) is exactly
    -1/2 < x < 1/2 and that of (1, 0) is 1/2 < x < 3/2. Largest exponent log 0.7."""

    def step(self, x, y):
        return x - 0.3 * math.sin(2 * math.pi * x) / (2 * math.pi), 0.5 * y

    def jacobian(self, x, y):
        return np.array([[1 - 0.3 * math.cos(2 * math.pi * x), 0.0], [0.0, 0.5]])


class CycleOrChaos(_Map):
    """y -> (y + sign y) / 2 (to +1 or -1, never crossing 0); x -> r x (1 - x) with r = 3.2 for
    y > 0 (a stable period-2 orbit, x = (r + 1 -+ sqrt((r - 3)(r + 1))) / (2 r)) and r = 3.9 for
    y < 0 (chaos on an interval). The basins are exactly the half planes."""

    def step(self, x, y):
        r = 3.2 if y > 0 else 3.9
        return r * x * (1 - x), 0.5 * (y + math.copysign(1.0, y))

    def jacobian(self, x, y):
        r = 3.2 if y > 0 else 3.9
        return np.array([[r * (1 - 2 * x), 0.0], [0.0, 0.5]])


# tolerances of the test maps (order-one states): the box 1e-3 lies well inside both basins (the
# boundaries are 1/2 away from the attractors); tight 1e-10 is far above the 1e-16 the contracting
# maps settle to; reading 1e-6; cells of 0.02 cut the chaotic interval (0.1..0.98) into ~45
SETTINGS = dict(box=(1e-3, 1e-3), tight=(1e-10, 1e-10), reading=(1e-6, 1e-6), cell=(0.02, 0.02))


def test_two_wells_every_start_labelled_by_its_exact_basin():
    rng = np.random.default_rng(1)
    starts = np.column_stack([rng.uniform(-0.5, 1.5, 300), rng.uniform(-1, 1, 300)])
    d = discover(TwoWells(), starts, RecurrenceSettings(**SETTINGS))
    assert len(d.attractors) == 2
    for a in d.attractors:
        assert a.period == 1 and a.kind == "periodic"
        assert min(np.abs(a.points[0] - [0.0, 0.0]).max(), np.abs(a.points[0] - [1.0, 0.0]).max()) < 1e-9
        assert a.exponent == pytest.approx(math.log(0.7), abs=0.02)  # 400 steps from the settled point
    at_one = next(k + 1 for k, a in enumerate(d.attractors) if a.points[0, 0] > 0.5)
    expected = np.where(starts[:, 0] > 0.5, at_one, 3 - at_one)
    np.testing.assert_array_equal(d.labels, expected)
    rows = basin_fractions(d.labels, {1: "a", 2: "b", UNRESOLVED: "unresolved"})
    assert rows[0]["cells"] + rows[1]["cells"] == 300 and rows[2]["cells"] == 0
    n_one = int(np.count_nonzero(starts[:, 0] > 0.5))
    assert rows[at_one - 1]["fraction"] == n_one / 300
    assert rows[0]["se"] == pytest.approx(math.sqrt(rows[0]["fraction"] * (1 - rows[0]["fraction"]) / 300))


def test_period_two_and_chaos_found_and_told_apart():
    rng = np.random.default_rng(2)
    starts = np.column_stack([rng.uniform(0.02, 0.98, 80), rng.uniform(-1, 1, 80)])
    s = RecurrenceSettings(**SETTINGS, recur=50, record=400, confirm_cloud=30, max_iterations=3000)
    d = discover(CycleOrChaos(), starts, s)
    kinds = sorted((a.kind, a.period) for a in d.attractors)
    assert kinds == [("chaotic", 0), ("periodic", 2)]
    cycle = next(a for a in d.attractors if a.period == 2)
    r = 3.2
    exact = sorted([(r + 1 - math.sqrt((r - 3) * (r + 1))) / (2 * r), (r + 1 + math.sqrt((r - 3) * (r + 1))) / (2 * r)])
    np.testing.assert_allclose(sorted(cycle.points[:, 0]), exact, atol=1e-9)
    chaos = next(a for a in d.attractors if a.period == 0)
    assert chaos.exponent > CHAOTIC_EXPONENT
    assert chaos.points[:, 0].min() > 0.09 and chaos.points[:, 0].max() <= 3.9 / 4  # the interval [f(r/4), r/4]
    label_of = {a.period: k + 1 for k, a in enumerate(d.attractors)}
    np.testing.assert_array_equal(d.labels, np.where(starts[:, 1] > 0, label_of[2], label_of[0]))


def test_known_attractors_catch_later_starts_early():
    s = RecurrenceSettings(**SETTINGS)
    first = discover(TwoWells(), [[0.3, 0.5], [0.7, -0.5]], s)
    again = discover(TwoWells(), [[0.2, 0.1], [0.9, 0.1]], s, known=first.attractors)
    assert len(again.attractors) == 2 and sorted(again.labels) == [1, 2]
    # a known orbit catches once `confirm` points lie in its boxes; a new one needs the tight tail
    fresh = discover(TwoWells(), [[0.2, 0.1], [0.9, 0.1]], s)
    assert np.all(again.iterations < fresh.iterations)


def test_smooth_boundary_has_the_box_entropy_of_its_cut():
    # 50 columns of x over (-1/2, 3/2) (none on the boundary x = 1/2), 4 rows, boxes of 4 x 4 cells:
    # 12 box columns; box column 6 (columns 24..27) holds 1 column of one basin and 3 of the other,
    # every other box is pure: S_b = H(1/4) / 12, S_bb = H(1/4) < log 2 (a smooth boundary)
    x = -0.5 + (np.arange(50) + 0.5) * 2 / 50
    v = np.linspace(-0.9, 0.9, 4)
    starts = np.array([(xi, vi) for vi in v for xi in x])
    d = discover(TwoWells(), starts, RecurrenceSettings(**SETTINGS))
    assert len(d.attractors) == 2
    e = basin_entropy(d.labels.reshape(4, 50), grid_boxes((4, 50), 4))
    h = -(0.25 * math.log(0.25) + 0.75 * math.log(0.75))
    assert e.boxes == 12 and e.boundary_boxes == 1 and e.boundary_fraction == pytest.approx(1 / 12)
    assert e.entropy == pytest.approx(h / 12, rel=1e-12)  # exact counts: only rounding
    assert e.boundary_entropy == pytest.approx(h, rel=1e-12) and not e.fractal


def test_entropy_of_a_uniform_mixture_passes_the_log_two_test():
    labels = np.tile([1, 2, 3], 300)  # every box holds the three colours equally: S_i = log 3
    e = basin_entropy(labels, np.repeat(np.arange(100), 9))
    assert e.entropy == pytest.approx(math.log(3)) and e.boundary_fraction == 1.0 and e.fractal


def test_sample_boxes_and_bad_input():
    ids = sample_boxes([[0.1, 0.1], [0.9, 0.9], [1.0, 0.0]], [0, 0], [1, 1], 2)
    assert ids.tolist() == [0, 3, 2]
    with pytest.raises(ValueError, match="no box holds"):
        basin_entropy([1, 2], [0, 1])
    with pytest.raises(ValueError, match="starts must be"):
        discover(TwoWells(), np.zeros((0, 2)), RecurrenceSettings(**SETTINGS))
    with pytest.raises(ValueError, match="box must be"):
        RecurrenceSettings(box=(0.0, 1.0), tight=(1, 1), reading=(1, 1), cell=(1, 1))


class SlowFlip(_Map):
    """x -> -0.97 x, y -> y / 2: one stable fixed point whose multiplier is near -1. Iterates
    approach it alternating sides and repeat every 2 steps long before every step."""

    def step(self, x, y):
        return -0.97 * x, 0.5 * y

    def jacobian(self, x, y):
        return np.array([[-0.97, 0.0], [0.0, 0.5]])


def test_a_slow_flip_is_period_one_not_two():
    d = discover(SlowFlip(), [[0.3, 0.2], [-0.2, 0.1]], RecurrenceSettings(**SETTINGS))
    assert [a.period for a in d.attractors] == [1] and d.labels.tolist() == [1, 1]
    assert np.abs(d.attractors[0].points).max() < 1e-8  # tight 1e-10 over one step: within 1e-10 / 1.97 / (1 - 0.97)
