"""The event-driven numba core: the DOP853 and Radau steppers, the pieces and their events,
and the ``simulate`` API on top of it."""
