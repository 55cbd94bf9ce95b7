"""Benchmarks and validation: speed of the core, work-precision, hard cases (workflow targets, not unit tests)."""
