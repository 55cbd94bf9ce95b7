"""The parameters identification fits: model BC per unit mass, with the contact law's constants.

Why per unit mass: a displacement record sees only x'' = F / m, so every force constant enters
as its ratio to m and m itself is not identifiable; it is given (model BC's mass unless the
user says otherwise) and the fitted ratios are multiplied by it to give a ModelParams.  eps (the
friction regularisation) and the contact exponents n1 = n2 = 3/2 are fixed: eps is a numerical
device far below any measurable velocity, and the Hertz exponent is the contact law's choice.

The fitted vector theta is ordered as NAMES; which entries are free is a boolean mask, so a
nested contact law (b = 0, n3 = 1) or a model without dry friction (T = 0) is the same vector
with entries fixed.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactosc.model.parameters import P_B, P_C, P_K, P_KI, P_M0E, P_N3, P_T, P_XI, ModelParams

__all__ = [
    "NAMES",
    "FIELDS",
    "UNITS",
    "LOWER",
    "UPPER",
    "theta_of",
    "params_of",
    "fill_array",
]

#: Fitted quantities, in the order of theta.
NAMES = ("k/m", "c/m", "T/m", "m0e/m", "kI/m", "b", "n3", "xI")
#: The ModelParams field behind each name (per unit mass ones are multiplied by m).
FIELDS = ("k", "c", "T", "m0e", "kI", "b", "n3", "xI")
PER_MASS = (True, True, True, True, True, False, False, False)
UNITS = ("1/s^2", "1/s", "m/s^2", "m", "1/(m^0.5 s^2)", "(s/m)^n3", "1", "m")
#: Where the core's p array holds each field.
_INDEX = (P_K, P_C, P_T, P_M0E, P_KI, P_B, P_N3, P_XI)
#: Physical bounds of theta (the Levenberg-Marquardt steps are projected onto them).
LOWER = np.array([1.0, 0.0, 0.0, 1e-6, 1e3, 0.0, 0.02, -np.inf])
UPPER = np.array([np.inf, np.inf, np.inf, np.inf, np.inf, 20.0, 2.0, np.inf])


def theta_of(params: ModelParams) -> np.ndarray:
    """theta (NAMES order) of a ModelParams."""
    return np.array(
        [getattr(params, f) / (params.m if pm else 1.0) for f, pm in zip(FIELDS, PER_MASS)],
        dtype=float,
    )


def params_of(theta, base: ModelParams) -> ModelParams:
    """ModelParams with the fitted fields from theta, the rest (m, eps, n1, n2) from base."""
    values = {f: float(v) * (base.m if pm else 1.0) for f, v, pm in zip(FIELDS, theta, PER_MASS)}
    return dataclasses.replace(base, **values)


def fill_array(p: np.ndarray, theta, m: float) -> None:
    """Write theta into the core's parameter array p (in place; no ModelParams, no warnings)."""
    for i, (idx, pm) in enumerate(zip(_INDEX, PER_MASS)):
        p[idx] = theta[i] * (m if pm else 1.0)
