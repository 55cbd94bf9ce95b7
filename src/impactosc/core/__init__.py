"""The event-driven numba core: the DOP853 and Radau steppers, the pieces and their events,
and the ``simulate`` API on top of it."""

from impactosc._lazy import export

export(
    globals(),
    {
        "simulate": "impactosc.core.simulation",
        "SimulationResult": "impactosc.core.simulation",
        "Window": "impactosc.core.simulation",
        "StallError": "impactosc.core.simulation",
        "warm_up": "impactosc.core.simulation",
        "DEFAULT_RTOL": "impactosc.core.simulation",
        "DEFAULT_ATOL": "impactosc.core.simulation",
    },
)
