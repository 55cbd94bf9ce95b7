"""Periodic orbits of model BC, stable or not: shooting on the stroboscopic map and Floquet
multipliers (continuation and bifurcation points build on it)."""

from .shooting import PeriodicOrbit, ShootingError, monodromy, shoot, stroboscopic_map
from .variational import variational_monodromy

__all__ = ["PeriodicOrbit", "ShootingError", "monodromy", "shoot", "stroboscopic_map", "variational_monodromy"]
