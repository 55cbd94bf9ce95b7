"""Measured records: reading and validating them, extracting impact events from sampled
displacement, and the labelled surrogate (the model sampled like a rig)."""
