"""The Cython shim through which the peer benchmark drives CyRK's C++ solvers with events.

CyRK 0.20's Python entries do not combine a compiled right-hand side with events (see
cyrk_runs.py), so this ~40-line shim builds the C++ ``Event`` objects around numba cfuncs and calls
``cysolve_ivp_noreturn`` from CyRK's own binary. It is compiled on first use into
$XDG_CACHE_HOME/impactosc/cyrk-shim-<hash> (the hash covers the shim and the CyRK, Cython and
numpy versions and the Python ABI), under a file lock, in a subprocess.
"""

from __future__ import annotations

import hashlib
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

INSTALL_HINT = "pip install -e '.[peers]'"


class PeerUnavailable(RuntimeError):
    """A peer solver is not installed or its shim cannot be built; the message says why."""


# --- CyRK: the Cython shim ----------------------------------------------------------------

SHIM_SOURCE = '''\
# distutils: language = c++
# cython: language_level=3, boundscheck=False, wraparound=False
"""impactosc's shim: CyRK's cysolve_ivp_noreturn with a cfunc right-hand side and cfunc events."""
from libc.stdint cimport uintptr_t
from libcpp.limits cimport numeric_limits
from libcpp.vector cimport vector

from CyRK.cy.common cimport DiffeqFuncType, MAX_STEP
from CyRK.cy.cysolver_api cimport CySolverBase, CySolverResult, ODEMethod, WrapCySolverResult, cysolve_ivp_noreturn
from CyRK.cy.events cimport Event, EventFunc


def solve(uintptr_t diffeq_address, list event_addresses, list event_directions, int method,
          double t_start, double t_end, const double[::1] y0, const double[::1] args,
          double rtol, double atol, const double[::1] t_eval, size_t max_num_steps):
    """Integrate with one event per address (direction +1, -1 or 0: CyRK's convention).

    Returns CyRK's WrapCySolverResult and where the solver stopped (t, [y]): the solver is
    retained for this, so that a run that fails tells how far it got.
    """
    cdef vector[double] y0_vec = vector[double](y0.shape[0])
    cdef vector[double] t_eval_vec = vector[double](t_eval.shape[0])
    cdef vector[char] args_vec = vector[char](args.shape[0] * sizeof(double))
    cdef double* args_ptr = <double*>args_vec.data()
    cdef vector[Event] events_vec = vector[Event]()
    cdef Py_ssize_t i
    for i in range(y0.shape[0]):
        y0_vec[i] = y0[i]
    for i in range(t_eval.shape[0]):
        t_eval_vec[i] = t_eval[i]
    for i in range(args.shape[0]):
        args_ptr[i] = args[i]
    cdef uintptr_t address
    cdef int direction
    for address, direction in zip(event_addresses, event_directions):
        events_vec.emplace_back(<EventFunc>address, numeric_limits[size_t].max(), direction)
    cdef WrapCySolverResult result = WrapCySolverResult()
    result.build_cyresult(<ODEMethod>method)
    cdef CySolverResult* result_ptr = result.cyresult_uptr.get()
    with nogil:
        # positionally: with keywords Cython compiles this call as a Python call (not without the GIL)
        cysolve_ivp_noreturn(result_ptr, <DiffeqFuncType>diffeq_address, t_start, t_end, y0_vec,
                             rtol, atol, args_vec, 0, max_num_steps, 2000, False, t_eval_vec, NULL,
                             events_vec, vector[double](), vector[double](), MAX_STEP, 0.0, 0, True, NULL)
    result.finalize()
    cdef CySolverBase* solver = result_ptr.solver_uptr.get()
    if solver == NULL:  # the setup failed; the result's message says why
        return result, float("nan"), [float("nan")] * y0.shape[0]
    return result, solver.t_now, [solver.y_now_ptr[i] for i in range(y0.shape[0])]
'''

_BUILD_SCRIPT = """\
import sys
import CyRK, numpy
from Cython.Build import cythonize
from setuptools import Extension, setup
name = sys.argv[1]
ext = Extension(name, [name + ".pyx"], language="c++", include_dirs=CyRK.get_include() + [numpy.get_include()],
                extra_compile_args=["-O0", "-std=c++20"],
                define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_9_API_VERSION")])
setup(ext_modules=cythonize([ext], quiet=True), script_args=["build_ext", "--inplace"])
"""


def _import_cyrk():
    try:
        import CyRK
    except ImportError as e:
        raise PeerUnavailable(f"CyRK is not installed ({e}); install the peers extra: {INSTALL_HINT}") from e
    return CyRK


def _shim_key(cyrk_version: str) -> str:
    import Cython

    digest = hashlib.sha256()
    for part in (
        SHIM_SOURCE,
        _BUILD_SCRIPT,
        cyrk_version,
        Cython.__version__,
        np.__version__,
        sys.implementation.cache_tag,
        importlib.machinery.EXTENSION_SUFFIXES[0],
    ):
        digest.update(part.encode() + b"\0")
    return digest.hexdigest()[:16]


def shim_dir(key: str) -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "impactosc" / f"cyrk-shim-{key}"


def _built(directory: Path, name: str) -> Path | None:
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        if (directory / (name + suffix)).is_file():
            return directory / (name + suffix)
    return None


def _build_shim(directory: Path, name: str) -> Path:
    """Compile the shim into `directory` once; concurrent callers wait on a file lock."""
    import fcntl

    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if (path := _built(directory, name)) is not None:
            return path
        with tempfile.TemporaryDirectory(dir=directory) as tmp:
            Path(tmp, name + ".pyx").write_text(SHIM_SOURCE)
            r = subprocess.run([sys.executable, "-c", _BUILD_SCRIPT, name], cwd=tmp, capture_output=True, text=True)
            built = _built(Path(tmp), name)
            if r.returncode != 0 or built is None:
                tail = "\n".join((r.stderr or r.stdout).strip().splitlines()[-15:])
                raise PeerUnavailable(
                    f"the CyRK shim could not be built (needs Cython, setuptools and a C++20 "
                    f"compiler; {INSTALL_HINT}):\n{tail}"
                )
            os.replace(built, directory / built.name)  # atomic: a reader never sees half a library
        return directory / built.name


def load_cyrk_shim():
    """The compiled shim module (built on first use); raises PeerUnavailable with the reason."""
    cyrk = _import_cyrk()
    try:
        import Cython  # noqa: F401  (the build needs it; say so before starting a compiler)
    except ImportError as e:
        raise PeerUnavailable(f"Cython is needed to build the CyRK shim; {INSTALL_HINT}") from e
    key = _shim_key(cyrk.__version__)
    name = f"_impactosc_cyrk_shim_{key}"
    if name in sys.modules:  # an extension module cannot be initialised twice in a process
        return sys.modules[name]
    directory = shim_dir(key)
    path = _built(directory, name) or _build_shim(directory, name)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module


def cyrk_method(name: str) -> int:
    """CyRK's integer code of an integration method (names as in METHODS, any case)."""
    from CyRK import ODEMethod

    try:
        return int(getattr(ODEMethod, name.upper()))
    except AttributeError:
        raise PeerUnavailable(f"CyRK {_import_cyrk().__version__} has no method {name!r}") from None


# --- the model as CyRK sees it --------------------------------------------------------------
