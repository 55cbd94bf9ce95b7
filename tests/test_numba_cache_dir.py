"""Where the compiled core is cached: a directory keyed on this tree's core sources, set without
importing numba; a NUMBA_CACHE_DIR the user chose is respected, one inherited from another
process's automatic choice is not (it may belong to other sources)."""

import os
import subprocess
import sys

import impactosc

PROBE = "import sys, impactosc; print('numba' in sys.modules); from numba.core import config; print(config.CACHE_DIR)"


def _probe(env_extra, prefix=""):
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "IMPACTOSC_AUTO_NUMBA_CACHE_DIR")}
    out = subprocess.run(
        [sys.executable, "-c", prefix + PROBE], env=env | env_extra, capture_output=True, text=True, check=True
    )
    imported, cache_dir = out.stdout.split()
    return imported == "True", cache_dir


def test_default_is_keyed_on_core_sources_and_numba_stays_unimported():
    imported, cache_dir = _probe({})
    assert not imported
    assert cache_dir == impactosc._core_cache_dir()


def test_user_choice_is_respected():
    assert _probe({"NUMBA_CACHE_DIR": "/tmp/chosen"})[1] == "/tmp/chosen"


def test_inherited_automatic_choice_is_recomputed_also_after_numba_import():
    stale = {"NUMBA_CACHE_DIR": "/tmp/other-tree", "IMPACTOSC_AUTO_NUMBA_CACHE_DIR": "/tmp/other-tree"}
    assert _probe(stale)[1] == impactosc._core_cache_dir()
    assert _probe(stale, prefix="import numba; ")[1] == impactosc._core_cache_dir()
