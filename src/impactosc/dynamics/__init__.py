"""What runs the core many times: sweeps and 2-D maps, periodic orbits (shooting, Floquet
multipliers, continuation, bifurcation points), grazing, Lyapunov exponents and basins."""

from impactosc.dynamics.shooting import PeriodicOrbit, ShootingError, monodromy, shoot, stroboscopic_map
from impactosc.dynamics.variational import variational_monodromy

__all__ = ["PeriodicOrbit", "ShootingError", "monodromy", "shoot", "stroboscopic_map", "variational_monodromy"]
