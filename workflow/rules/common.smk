# Helpers shared by all rules: configuration validation, the numba cache location, and the
# target lists that each rules file extends (rule all and the numbers table collect them).
import os

from impactosc.config import validate_config

config = validate_config(config, workflow.source_path("../schemas/config.schema.yaml"))

# One known on-disk cache for the numba core, shared by every job; the numba_cache rule
# fills it once before any simulation runs, so parallel jobs only ever read it.
os.environ.setdefault("NUMBA_CACHE_DIR", os.path.abspath(".numba_cache"))

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
