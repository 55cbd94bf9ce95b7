"""Periodic orbits of model BC, stable or not: shooting on the stroboscopic map and Floquet
multipliers (continuation and bifurcation points build on it)."""

from impactosc.periodic_orbits.shooting import PeriodicOrbit, ShootingError, monodromy, shoot, stroboscopic_map
from impactosc.periodic_orbits.variational import variational_monodromy

__all__ = ["PeriodicOrbit", "ShootingError", "monodromy", "shoot", "stroboscopic_map", "variational_monodromy"]
