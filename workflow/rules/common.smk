# Helpers shared by all rules: configuration validation, the numba cache location, and the
# target lists that each rules file extends (rule all and the numbers table collect them).
from pathlib import Path

import impactosc
from impactosc.config import validate_config

config = validate_config(config, workflow.source_path("../schemas/config.schema.yaml"))

# The numba core's on-disk cache is keyed on a hash of the core sources (impactosc/__init__.py)
# and shared by every job; the numba_cache rule fills it once, whenever those sources
# change, before any simulation runs, so parallel jobs only ever read it.
CORE_SOURCES = [str(Path(impactosc.__file__).parent / name) for name in impactosc.CORE_SOURCES]

# Each rules file appends its final products here (figures as figNN.png/.pdf, tables ...).
ALL_TARGETS = []
# Each figure group appends the CSV of its rows of the paper-vs-replication table here.
TABLE_ROWS = []


def scene(name):
    """The validated config entry of one scene."""
    return config["scenes"][name]


def figure(nn):
    """PNG and PDF paths of paper figure NN (two-digit string or int)."""
    return [f"results/figures/fig{int(nn):02d}.png", f"results/figures/fig{int(nn):02d}.pdf"]
