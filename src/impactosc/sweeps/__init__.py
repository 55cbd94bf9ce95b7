"""Sweeps in a parameter: continuation of the attractor in w, chunked for parallel jobs
(continuation), and the 2-D maps over (w, a second parameter) (maps)."""
