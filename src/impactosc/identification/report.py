"""What an identification leaves behind: the model file, the parameter table, the fit's windows.

Why here and not in the driver: the fit works in theta (per unit mass); a user reads ModelParams
fields with their units, and the model file is how the model travels to every command and the
workflow (:mod:`impactosc.model.model_file`).
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import h5py
import numpy as np

from impactosc.identification.fitted_parameters import ALL_FIELDS, PER_MASS, QUANTITIES, quantity_unit
from impactosc.identification.staged_fit import Identification
from impactosc.io.files import atomic_write, stamp_h5
from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import unit_of

__all__ = [
    "configured_inputs",
    "stated_model",
    "parameter_markdown",
    "parameter_table",
    "write_identified_model",
    "write_fit_windows",
    "read_fit_windows",
]

_NOT_FITTED = {
    "m": "given: the mass is not identifiable from displacement",
    "eps": "fixed: the friction regularisation is a numerical device, far below any measured velocity",
    "n1": "fixed: the contact law's exponent",
    "n2": "fixed: the contact law's exponent",
}


def _sha256(path) -> str | None:
    p = Path(str(path))
    if not p.is_file():
        return None
    return hashlib.sha256(p.read_bytes()).hexdigest()


def parameter_table(ident: Identification, truth=None) -> list[dict]:
    """One row per quantity of the identified law: per unit mass and as a ModelParams field, with errors.

    truth: the model the records sample, when known (a surrogate's,
    :func:`impactosc.records.surrogate.record_truth`): each row then has ``truth`` (field units)
    and ``z``, the error in standard errors (value - truth) / stderr of the fitted ones.
    """
    m = ident.params.m
    rows = []
    for i, nm in enumerate(ident.quantities):
        j = QUANTITIES.index(nm)
        scale = m if PER_MASS[j] else 1.0
        se = float(ident.stderr[i]) if ident.free[i] else math.nan
        row = {
            "quantity": nm,
            "value": float(ident.theta[i]),
            "stderr": se,
            "relative_stderr": se / abs(ident.theta[i]) if ident.theta[i] != 0 else math.nan,
            "field": ALL_FIELDS[j],
            "field_value": float(ident.theta[i]) * scale,
            "field_stderr": se * scale,
            "unit": unit_of(ALL_FIELDS[j], ident.params.n1),
            "start": float(ident.start[i]) * scale,
            "status": "fitted" if ident.free[i] else ident.fixed.get(nm, "fixed"),
        }
        if truth is not None:
            row["truth"] = float(getattr(truth, ALL_FIELDS[j]))
            fitted = ident.free[i] and row["field_stderr"] > 0
            row["z"] = (row["field_value"] - row["truth"]) / row["field_stderr"] if fitted else math.nan
        rows.append(row)
    return rows


def write_identified_model(path, ident: Identification, *, name: str | None = None) -> Path:
    """The model file of an identification: parameters, standard errors, the covariance of the
    fitted quantities (full precision) and their correlation (rounded, for reading), records."""
    m = ident.params.m
    stderr, fixed = {}, dict(_NOT_FITTED)
    for i, nm in enumerate(ident.quantities):
        j = QUANTITIES.index(nm)
        if ident.free[i]:
            stderr[ALL_FIELDS[j]] = float(ident.stderr[i]) * (m if PER_MASS[j] else 1.0)
        else:
            fixed[ALL_FIELDS[j]] = ident.fixed.get(nm, "fixed")
    records = [{**r, "sha256": _sha256(r["path"])} for r in ident.records]
    res = ident.fit
    return write_model_file(
        path,
        ident.params,
        stderr=stderr,
        fixed=fixed,
        covariance=(ident.free_names, [quantity_unit(nm, ident.params.n1) for nm in ident.free_names], ident.fit.cov),
        correlation=(ident.free_names, np.round(ident.correlation, 6)),
        records=records,
        fit={
            "method": "multiple shooting (one start state per window), Levenberg-Marquardt",
            "window_periods": ident.periods,
            "n_windows": int(ident.windows.size),
            "n_samples": int(res.n_samples),
            "residual_rms_m": ident.noise,
            "iterations": int(res.iterations),
            "converged": bool(res.converged),
            "seconds": round(ident.seconds, 2),
            "stderr_note": "standard errors from the Jacobian, scaled by the residual variance",
        },
        name=name or "identified from " + ", ".join(r["label"] for r in ident.records),
    )


def write_fit_windows(path, ident: Identification, prediction: np.ndarray, *, sources=None) -> Path:
    """The fitted windows (samples, model, record of each) for the identification figure."""
    w = ident.windows
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        g = f.create_group("windows")
        g.create_dataset("x", data=w.y, compression="gzip")
        g.create_dataset("x_model", data=prediction, compression="gzip")
        for k in ("record", "start", "n", "offset"):
            g.create_dataset(k, data=getattr(w, k))
        g.create_dataset("t_start", data=w.tau0)
        g.create_dataset("dt", data=w.dt)
        g.create_dataset("omega", data=w.omega)
        f.attrs["labels"] = list(w.labels)
        f.attrs["residual_rms_m"] = ident.noise
        stamp_h5(
            f,
            sources=sources,
            units={"x_model": "m", "record": "1", "start": "1", "n": "1", "offset": "1", "t_start": "s", "dt": "s"},
        )
    return Path(path)


def read_fit_windows(path) -> dict:
    with h5py.File(path, "r") as f:
        out = {k: f["windows"][k][()] for k in f["windows"]}
        out["labels"] = [str(s) for s in f.attrs["labels"]]
        out["residual_rms_m"] = float(f.attrs["residual_rms_m"])
    return out


def _value(v, se):
    if not math.isfinite(se) or se <= 0:
        return f"{v:.6g}"
    return f"{v:.6g} +- {se:.2g}"


def parameter_markdown(rows: list[dict], ident: Identification) -> str:
    """The parameter table as Markdown, with the fit's residual and window counts."""
    truth = bool(rows) and "truth" in rows[0]
    lines = [
        f"# Identified model ({', '.join(r['label'] for r in ident.records)})",
        "",
        f"Multiple shooting on {ident.windows.size} windows of {ident.periods:g} forcing periods, "
        f"{ident.fit.n_samples} samples; residual rms {ident.noise * 1e6:.3f} um; "
        f"{ident.fit.iterations} iterations of the last stage, {'converged' if ident.fit.converged else 'NOT converged'}; "
        f"{ident.seconds:.1f} s. Standard errors from the Jacobian, scaled by the residual variance.",
        "",
        "| parameter | value +- standard error | relative | unit | status |"
        + (" truth | error / stderr |" if truth else ""),
        "|---|---|---|---|---|" + ("---|---|" if truth else ""),
    ]
    for r in rows:
        rel = f"{r['relative_stderr']:.2e}" if math.isfinite(r["relative_stderr"]) else ""
        line = f"| {r['field']} | {_value(r['field_value'], r['field_stderr'])} | {rel} | {r['unit']} | {r['status']} |"
        if truth:
            z = f"{r['z']:+.2f}" if math.isfinite(r["z"]) else ""
            line += f" {r['truth']:.6g} | {z} |"
        lines.append(line)
    if truth:
        lines += [
            "",
            "truth: the model the surrogate records sample (their metadata); a fit that holds has |z| < 2 mostly.",
        ]
    return "\n".join(lines) + "\n"


def stated_model(section: dict, model: dict):
    """The stated model of the workflow's identification config: the study's model (its
    contact law included) with the configured mass."""
    import dataclasses

    from impactosc.model.parameters import ModelParams

    base = ModelParams(**model)
    if section["mass"] is not None:
        base = dataclasses.replace(base, m=float(section["mass"]))
    return base


def configured_inputs(section: dict, model: dict, paths) -> tuple:
    """(stated model, records) of the workflow's identification config: :func:`stated_model`,
    and the record files read as ``section["read"]`` says."""
    from impactosc.records.formats import read_records

    read = {k: v for k, v in section["read"].items() if v is not None}
    return stated_model(section, model), read_records(list(paths), duration=section.get("duration"), **read)
