# Helpers shared by all rules: configuration validation and the numba cache location.
import os

from impactosc.config import validate_config

config = validate_config(config, workflow.source_path("../schemas/config.schema.yaml"))

# One known on-disk cache for the numba core, shared by every job; the numba_cache rule
# fills it once before any simulation runs, so parallel jobs only ever read it.
os.environ.setdefault("NUMBA_CACHE_DIR", os.path.abspath(".numba_cache"))


def scene(name):
    """The validated config entry of one scene."""
    return config["scenes"][name]
