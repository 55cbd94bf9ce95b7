"""One look for every figure, and atomic PNG + PDF output.

Figures are sized for print (single column 8.5 cm, double 17 cm) with the Agg backend, so
they render identically on a headless CI machine.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from impactosc.io.files import atomic_write

CM = 1 / 2.54
SINGLE = 8.5 * CM
DOUBLE = 17.0 * CM

STYLE = {
    "font.size": 8,
    "axes.labelsize": 8,
    "axes.titlesize": 8,
    "legend.fontsize": 7,
    "xtick.labelsize": 7,
    "ytick.labelsize": 7,
    "lines.linewidth": 0.9,
    "axes.linewidth": 0.6,
    "savefig.dpi": 300,
    "figure.dpi": 150,
    "figure.constrained_layout.use": True,
    "pdf.fonttype": 42,
}


def apply_style() -> None:
    plt.rcParams.update(STYLE)


def model_label(source: dict | None) -> str:
    """How a figure names the model it was drawn for (config["model_source"]): "model BC", or
    "model <file name>" when a model file gave the parameters."""
    return f"model {Path(source['file']).name}" if source and source.get("file") else "model BC"


def save_figure(fig, *paths) -> None:
    """Save `fig` to each path (format from the suffix), each atomically, then close it."""
    for path in paths:
        path = Path(path)
        with atomic_write(path) as tmp:
            fig.savefig(tmp, format=path.suffix.lstrip("."))
    plt.close(fig)
