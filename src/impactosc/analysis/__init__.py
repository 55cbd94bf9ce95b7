"""Readings of simulated (or measured) runs: period detection, the periodic regime and its
grazing, bifurcation diagrams, the chaotic impact train and its ensemble."""
