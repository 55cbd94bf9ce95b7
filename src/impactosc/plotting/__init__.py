"""Plotting helpers shared by every figure script (style, saving)."""

from .style import apply_style, model_label, save_figure

__all__ = ["apply_style", "model_label", "save_figure"]
