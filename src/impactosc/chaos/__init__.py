"""Chaos measured, not only named: Lyapunov exponents of the stroboscopic map (lyapunov) and
the basins of coexisting attractors (basins)."""
