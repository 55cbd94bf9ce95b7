"""Plotting helpers shared by every figure script (style, saving)."""

from impactosc.plotting.style import apply_style, model_label, save_figure

__all__ = ["apply_style", "model_label", "save_figure"]
