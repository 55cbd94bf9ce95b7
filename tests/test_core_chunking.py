"""Chunked runs equal one long run bit for bit (the whole integrator state, including the
transformed-piece variables, is carried over between calls of the core)."""

import numpy as np

from impactosc.core.simulation import Window, simulate


def test_chunking_changes_nothing():
    kw = dict(window=Window(10.0, 20.0, 0.01))
    one = simulate(40.86, 5.0, 15.0, chunk_steps=10**9, **kw)
    many = simulate(40.86, 5.0, 15.0, chunk_steps=97, **kw)
    assert len(one.events["impacts"]["t"]) > 50
    for name, cols in one.events.items():
        for col, values in cols.items():
            np.testing.assert_array_equal(values, many.events[name][col], err_msg=f"{name}/{col}")
    np.testing.assert_array_equal(one.trajectory["x"], many.trajectory["x"])
    np.testing.assert_array_equal(one.final_state, many.final_state)


def test_only_events_after_transient_are_kept():
    res = simulate(40.86, 3.0, 2.0)
    for name, cols in res.events.items():
        assert np.all(cols["t"] >= 3.0), name
    assert set(res.events) == {"impacts", "penetrations", "near_misses", "poincare"}
    only = simulate(40.86, 3.0, 2.0, record=("impacts",))
    assert set(only.events) == {"impacts"}
    np.testing.assert_array_equal(only.events["impacts"]["t"], res.events["impacts"]["t"])
