"""Integration of model BC: parameters, the DOP853 and Radau steppers, the event-driven numba
core, the ``simulate`` API on top of it, and the independent SciPy reference."""
