"""The figure makers of the study, and the style and saving they share."""

from impactosc_study.figures.style import apply_style, model_label, save_figure

__all__ = ["apply_style", "model_label", "save_figure"]
