"""impactosc: forced impacting oscillator (model BC) and the statistics of its impact events."""

__version__ = "0.1.0"
