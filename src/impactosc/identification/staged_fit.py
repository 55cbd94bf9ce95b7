"""Identify a model's parameters from records: the driver of the multiple-shooting fit.

Why in stages of growing windows: the start values (:mod:`.start`) are a few per cent off, and
over two forcing periods a few per cent in k/m or kI/m move the impacts far enough that a
window's fit can settle on another trajectory.  Over half a period the same error is small; each
stage (``STAGES`` forcing periods per window) starts from the previous stage's parameters,
and the last, longest windows give the estimate and its covariance (the longer the window, the
fewer start states the samples pay for).

After the fit, a free parameter the records hardly constrain (a standard error beyond
``UNPINNED``, e.g. n3 when the fitted damping b is near 0, or kI/m with a handful of contacts)
is fixed at its stated value and the fit repeated: a number with an error bar wider than its
range is noise, not an estimate.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from impactosc.identification.continuity import fit_continuous, links
from impactosc.identification.fitted_parameters import (
    LOWER,
    PER_MASS,
    QUANTITIES,
    UPPER,
    law_quantities,
    params_of,
    quantity_unit,
    theta_of,
)
from impactosc.identification.least_squares import FitResult, carried_states, fit, fit_states
from impactosc.identification.start import start_values
from impactosc.identification.window_predictions import Predictor
from impactosc.identification.windows import WindowSet, check_forcing_phase, cut_windows
from impactosc.model.contact_laws import OWN_PARAMETERS
from impactosc.model.parameters import ModelParams
from impactosc.records.sample_fits import estimate_noise

__all__ = ["Identification", "identify", "STAGES", "UNPINNED"]

#: Window lengths of the stages, forcing periods.
STAGES = (0.5, 1.0, 2.0)
#: Convergence: no parameter moves by more than this fraction of its standard error (the
#: stages before the last only bring the start values closer: a loose test there).
FINAL_TOL, STAGE_TOL = 0.05, 0.3
#: A window whose rms residual exceeds this multiple of the median window's is left out.
OUTLIER = 1.5
#: A standard error beyond this (relative to the value for the ratios, absolute for b, n3, xI
#: and e: half of e's range is no estimate) means the records do not pin the parameter.
UNPINNED = {
    "k/m": 0.5,
    "c/m": 1.0,
    "T/m": 1.0,
    "m0e/m": 0.5,
    "kI/m": 0.5,
    "b": 1.0,
    "n3": 0.5,
    "xI": 1e-3,
    **{prm.quantity: prm.unpinned for prm in OWN_PARAMETERS.values()},  # the laws' own (e: 0.5, cI/m: 1)
}


@dataclass
class Identification:
    """The identified model and how well the records pin it: theta, stderr, free and start hold
    the quantities of its contact law (:attr:`quantities`, model BC's the eight NAMES), theta_all
    every entry of the core's theta (QUANTITIES)."""

    params: ModelParams
    theta: np.ndarray
    stderr: np.ndarray  # 0 for fixed entries
    free: np.ndarray
    correlation: np.ndarray  # of the free entries, in theta's order
    fixed: dict  # name -> why it is fixed
    noise: float  # residual std, m
    fit: FitResult
    windows: WindowSet
    start: np.ndarray
    seconds: float
    periods: float  # window length of the last stage, forcing periods
    records: list = field(default_factory=list)
    theta_all: np.ndarray | None = None

    @property
    def free_names(self) -> list:
        return [nm for nm, f in zip(self.quantities, self.free) if f]

    @property
    def quantities(self) -> tuple[str, ...]:
        """The quantities of the identified model's contact law (theta's other entries are not its own)."""
        return law_quantities(self.params.law)

    def prediction(self, rtol: float = 1e-10) -> np.ndarray:
        """The fitted model's samples of every window (like windows.y)."""
        pred = Predictor(self.windows, self.params.as_array(1.0), self.params.m, rtol=rtol)
        return pred.predict(self.theta_all, self.fit.states)

    def table(self) -> list[dict]:
        """One row per quantity of the law: value, standard error, unit, free or why fixed."""
        return [
            {
                "name": nm,
                "value": float(self.theta[i]),
                "stderr": float(self.stderr[i]) if self.free[i] else None,
                "unit": quantity_unit(nm, self.params.n1),
                "fixed": self.fixed.get(nm, ""),
            }
            for i, nm in enumerate(self.quantities)
        ]


def _unpinned(theta, se, free):
    """Free names whose standard error is beyond UNPINNED."""
    out = {}
    for i, nm in enumerate(QUANTITIES):
        if not free[i]:
            continue
        scale = abs(theta[i]) if PER_MASS[i] else 1.0
        if not se[i] <= UNPINNED[nm] * max(scale, 1e-300):
            out[nm] = f"standard error {se[i]:.3g} beyond {UNPINNED[nm]:g}{' x value' if scale != 1.0 else ''}"
    return out


def _well_fitted(res: FitResult, pred: Predictor) -> np.ndarray:
    """Mask of the windows whose rms residual is within OUTLIER times the median window's."""
    rms = np.sqrt(res.window_rss / pred.w.n)
    return rms <= OUTLIER * np.median(rms)


def _stage(records, theta, base_p, m, periods, level, rtol, keep=None, previous=None):
    """The stage's windows and their start states fitted at theta; ``previous``: the last
    stage's (Predictor, fitted states, mask of the well-fitted windows), whose trajectories give
    the start states' guesses."""
    windows = cut_windows(records, periods=periods, level=level)
    if keep is not None:
        windows = windows.subset(keep(windows))
    pred = Predictor(windows, base_p, m, rtol=rtol)
    if previous is None:
        guess, close = np.column_stack([windows.x0, windows.v0]), None
    else:
        guess, close = carried_states(*previous, theta, windows)
    states, _ = fit_states(pred, theta, guess, close=close)
    return pred, states


def _free_parameters(start: dict, fixed: dict | None, base: ModelParams) -> tuple[np.ndarray, np.ndarray, dict]:
    """The first theta, which of its entries are fitted, and why each other one is fixed: what
    the start values could not pin, what the caller fixes (`fixed`), and n3 without damping.
    The entries that are not the law's own (b and n3 of a restitution law, ...) are fixed at
    base's values and named nowhere."""
    theta = start["theta"].copy()
    own = law_quantities(base.law)
    free = np.array([nm in own for nm in QUANTITIES])
    theta[~free] = theta_of(base, full=True)[~free]
    why_fixed = {}
    for nm, why in start["unpinned"].items():
        if nm in own:
            free[QUANTITIES.index(nm)] = False
            theta[QUANTITIES.index(nm)] = theta_of(base, full=True)[QUANTITIES.index(nm)]
            why_fixed[nm] = f"not identifiable: {why}; fixed at the stated value"
    for nm, value in (fixed or {}).items():
        i = QUANTITIES.index(nm)
        free[i] = False
        theta[i] = theta_of(base, full=True)[i] if value is None else float(value)
        why_fixed[nm] = "fixed by the model's definition"
    if "b" in own and theta[QUANTITIES.index("b")] == 0.0:  # no damping: n3 does nothing
        i = QUANTITIES.index("n3")
        if free[i]:
            free[i] = False
            why_fixed["n3"] = "no effect without damping (b = 0)"
    return theta, free, why_fixed


def identify(
    records,
    *,
    base: ModelParams | None = None,
    fixed: dict | None = None,
    stages=STAGES,
    select: Callable[[WindowSet], np.ndarray] | None = None,
    rtol: float = 1e-10,
    start: dict | None = None,
    progress: Callable[[str], None] | None = None,
    continuity: bool = True,
) -> Identification:
    """Fit theta (fitted_parameters.QUANTITIES) to the records by multiple shooting.

    base : the stated model: its contact law, m, eps, n1, n2 and every fixed value (default
        model BC); the law's own quantities are fitted (:func:`law_quantities`: a restitution
        law's e, a viscous damping's cI/m, model BC's b and n3, ...).
    fixed : name -> value (None: base's) of the law's quantities not fitted (a nested contact
        law: {"b": 0.0}; no dry friction: {"T/m": 0.0}).
    select : windows -> mask of the windows to fit (default all; model choice holds some out).
    start : start values from an earlier call (skips the start-value fits).
    """
    t_start = time.perf_counter()
    say = progress or (lambda msg: None)
    base = base or ModelParams()
    own = law_quantities(base.law)
    for nm in fixed or {}:
        if nm not in own:
            raise ValueError(f"unknown parameter {nm!r} to fix for the {base.law} law; choose from {', '.join(own)}")
    records = list(records)
    if not records:
        raise ValueError("identification needs at least one record")
    check_forcing_phase(records)
    sigma = float(np.median([estimate_noise(r.x) for r in records]))
    if start is None:
        say(f"start values: contact fit and free-flight fit on {len(records)} record(s)")
        start = start_values(records, base, sigma=sigma)
    theta, free, why_fixed = _free_parameters(start, fixed, base)
    m = base.m
    base_p = base.as_array(1.0)
    level = theta[QUANTITIES.index("xI")]
    res = pred = previous = None
    for k, periods in enumerate(stages):
        for attempt in range(2):
            # (a refit after fixing a parameter starts afresh: the last stage's trajectories
            # belong to the parameters before)
            carry = previous if attempt == 0 else None
            pred, states = _stage(records, theta, base_p, m, periods, level, rtol, select, carry)
            say(f"stage {k + 1}/{len(stages)}: {pred.w.size} windows of {periods:g} forcing periods")
            last = k == len(stages) - 1
            res = fit(
                pred,
                theta,
                states,
                free,
                QUANTITIES,
                lower=LOWER,
                upper=UPPER,
                rel_step_tol=FINAL_TOL if last else STAGE_TOL,
            )
            if k < len(stages) - 1 or attempt == 1:
                break
            loose = _unpinned(res.theta, res.stderr, free)
            if not loose:
                break
            for nm, why in loose.items():  # fix what the records do not pin, then refit
                i = QUANTITIES.index(nm)
                free[i] = False
                theta[i] = theta_of(base, full=True)[i]
                why_fixed[nm] = f"not identifiable from these records ({why}); fixed at the stated value"
                say(f"{nm}: {why_fixed[nm]}")
            theta = np.where(free, res.theta, theta)
        theta = res.theta.copy()
        previous = (pred, res.states, _well_fitted(res, pred))
        say(f"  rms residual {math.sqrt(res.s2) * 1e6:.3f} um after {res.iterations} iterations")
    if continuity:
        # a window fitted far worse than the rest settled on another trajectory (a local minimum
        # of its start state): it would pull the parameters, so it leaves the fit (and is counted)
        keep = _well_fitted(res, pred)
        if not keep.all():
            say(f"  {int((~keep).sum())} of {keep.size} windows left out: rms above {OUTLIER:g} x the median")
            pred = Predictor(pred.w.subset(keep), pred.base, pred.m, rtol=rtol)
            res = dataclasses.replace(res, states=res.states[keep])
        say(f"continuity: {links(pred.w).size} joins between {pred.w.size} windows")
        res = fit_continuous(
            pred,
            res.theta,
            res.states,
            free,
            QUANTITIES,
            lower=LOWER,
            upper=UPPER,
            progress=lambda i, c, g: say(f"  step {i}: rms {math.sqrt(c / pred.w.y.size) * 1e6:.3f} um, gap {g:.2e} m"),
        )
        theta = res.theta.copy()
    own = [QUANTITIES.index(nm) for nm in law_quantities(base.law)]
    return Identification(
        params=params_of(theta, base),
        theta=theta[own],
        stderr=res.stderr[own],
        free=free[own],
        correlation=res.correlation,
        fixed=why_fixed,
        noise=math.sqrt(res.s2),
        fit=res,
        windows=pred.w,
        start=start["theta"][own],
        seconds=time.perf_counter() - t_start,
        periods=float(stages[-1]),
        records=[
            {"label": r.label, "path": r.path, "omega": r.omega, "duration": float(r.t[-1] - r.t[0])} for r in records
        ],
        theta_all=theta,
    )
