"""Model files: the one way a model of a rig travels between commands, the workflow and people.

Why a file: model BC was identified on one rig; another rig has its own parameters, their
standard errors, the records they came from and the code that fitted them. A YAML file
(``format: impactosc-model/1``) holds all of it, readable and diffable, and every command
line, the Python API and the workflow config read it through :func:`read_model_file`. Layout::

    format: impactosc-model/1
    name: rig 3, March                       # free text, optional
    contact: {law: flores, e: 0.7}           # optional: the contact law (model BC's without it);
                                             # a law other than bc has no b, n2, n3 in parameters
    noise: {seed: 0, motor: {rms: 0.5, tau: 0.2}, force: {rms: 0.05, tau: 0.05}}   # optional: noise in
                                             # the dynamics (impactosc.model.noise; none without it)
    parameters:                              # each ModelParams field: a number, or a mapping
      m:  {value: 8.735, unit: kg, fixed: true, note: given (mass is not identifiable)}
      k:  {value: 1418.9, unit: N/m, stderr: 3.1}
      xI: -2.086e-3                          # a plain number is a value in SI units
    covariance: {names: [k/m, c/m], units: [1/s^2, 1/s], matrix: [[0.25, 0.01], [0.01, 0.01]]}   # optional
    correlation: {names: [k/m, c/m], matrix: [[1.0, 0.2], [0.2, 1.0]]}   # optional, for reading
    records: [{path: run3.tdms, sha256: ..., omega: 40.86}]              # optional
    fit: {chi2_dof: 1.02, n_windows: 40}                                  # optional, free
    package_version: 0.1.0                   # written by write_model_file, with git_commit
    created: 2025-03-01T12:00:00+00:00       # and this timestamp

The covariance is that of the quantities the identification fitted (per unit mass), written at
full precision: a correlation rounded for reading is not positive definite when two quantities
correlate at 0.99 and more (b and n3 of a contact law), so uncertainty is propagated from the
covariance (:attr:`ModelFile.covariance`, checked symmetric positive definite when read).

A hand-written file may give a covariance in the parameters' own names and units (k, c, ...;
:func:`impactosc.identification.predictions.field_covariance` reads both), or each parameter's
``stderr`` and no covariance: independent errors. A key given twice (YAML keeps the last
silently), a name given twice in a covariance or correlation, a units list of another length
than its names and a correlation outside [-1, 1] are refused when the file is read.

A parameter the file leaves out takes model BC's value (:attr:`ModelFile.defaulted` names
them). Values are SI in the units of ``impactosc.model.parameters.PARAM_UNITS``; a unit
that differs is refused, not converted.
"""

from __future__ import annotations

import dataclasses
import datetime
import math
from pathlib import Path

import numpy as np
import yaml

from impactosc import __version__
from impactosc.io.files import atomic_write, git_commit
from impactosc.io.names import closest_name, shown, split_assignment
from impactosc.io.yaml_text import AliasError, DuplicateKeyError, load_yaml, yaml_problem
from impactosc.model.contact_laws import DEFAULT_LAW, LAWS, law_of
from impactosc.model.noise import Noise
from impactosc.model.parameters import PARAM_UNITS, PARAMETERS, ModelParams, unit_of

FORMAT = "impactosc-model/1"

#: The parameters a model file's ``parameters`` block holds (a law's own e and cI go in ``contact``)
NAMES = [name for name, _, _ in PARAMETERS]
BC_DESCRIPTION = "model BC (paper)"
_TOP_KEYS = (
    "format",
    "name",
    "contact",
    "noise",
    "parameters",
    "covariance",
    "correlation",
    "records",
    "fit",
    "package_version",
    "git_commit",
    "created",
)
_ENTRY_KEYS = ("value", "unit", "stderr", "fixed", "note")


@dataclasses.dataclass(frozen=True)
class ModelFile:
    """A model file as read: the parameters, their standard errors, the fixed ones (name ->
    why), everything else of the file (meta), its path and the parameters it left out."""

    params: ModelParams
    stderr: dict
    fixed: dict
    meta: dict
    path: str
    defaulted: tuple = ()

    @property
    def covariance(self) -> tuple[list, list, np.ndarray] | None:
        """(names, units, matrix) of the fitted quantities' covariance, when the file has one:
        symmetric and positive definite (checked when the file was read)."""
        cov = self.meta.get("covariance")
        if cov is None:
            return None
        return list(cov["names"]), list(cov.get("units", [])), _spd(cov["matrix"], len(cov["names"]), self.path)

    @property
    def noise(self) -> Noise:
        """The noise in the dynamics the file states (its ``noise`` block; none without one)."""
        return Noise.from_dict(self.meta.get("noise"))

    @property
    def correlation(self) -> tuple[list, np.ndarray] | None:
        """(names, matrix) of the parameters' correlation, when the file has one."""
        corr = self.meta.get("correlation")
        return None if corr is None else (list(corr["names"]), np.asarray(corr["matrix"], dtype=float))


def _spd(matrix, n, where) -> np.ndarray:
    """The covariance matrix as an n x n array, symmetrised (what is written), or a ValueError
    naming ``where`` when it is not square, not symmetric (beyond rounding) or not positive definite."""
    try:
        a = np.asarray(matrix, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: covariance: the matrix is not a table of numbers") from None
    if a.shape != (n, n) or not np.all(np.isfinite(a)):
        raise ValueError(f"{where}: covariance: need a finite {n} x {n} matrix for its {n} names, got shape {a.shape}")
    # a fit's covariance, the inverse of an ill-conditioned matrix, is symmetric to its rounding
    # (1e-10 of the scale and below); a matrix asymmetric beyond 1e-6 is not a covariance
    scale = np.sqrt(np.abs(np.outer(np.diag(a), np.diag(a))))
    if np.any(np.abs(a - a.T) > 1e-6 * scale):
        raise ValueError(f"{where}: covariance: the matrix is not symmetric")
    a = 0.5 * (a + a.T)
    try:
        np.linalg.cholesky(a)
    except np.linalg.LinAlgError:
        raise ValueError(
            f"{where}: covariance: the matrix is not positive definite (smallest eigenvalue "
            f"{np.linalg.eigvalsh(a)[0]:.3g}); it cannot describe the uncertainty of a fit"
        ) from None
    return a


def _unknown(key, names, what: str = "key", absent=()) -> str:
    """'unknown <what> (did you mean ...?)', or the known names when none is close."""
    guess = closest_name(key, names, absent)
    return f"unknown {what}" + (f" (did you mean {guess!r}?)" if guess else f"; known: {', '.join(names)}")


def _number(value, where: str) -> float:
    """A finite float from a YAML value (strings such as '1e-6', which YAML 1.1 does not
    read as a number, included); ValueError naming `where` otherwise."""
    try:
        if isinstance(value, bool):
            raise ValueError
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: {shown(value)} is not a number") from None
    if not math.isfinite(number):
        raise ValueError(f"{where}: {shown(value)} is not a finite number")
    return number


def _plain(obj):
    """Plain Python types for yaml.safe_dump: numpy arrays and scalars, tuples and paths."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    return obj


def _check_names(names, what: str) -> None:
    for name in names:
        if name not in PARAM_UNITS:
            raise ValueError(f"{what}: {name!r}: " + _unknown(name, list(PARAM_UNITS), "parameter"))


def write_model_file(
    path,
    params: ModelParams,
    *,
    stderr: dict | None = None,
    fixed: dict | None = None,
    correlation: tuple[list[str], np.ndarray] | None = None,
    covariance: tuple[list[str], list[str], np.ndarray] | None = None,
    records: list[dict] | None = None,
    fit: dict | None = None,
    name: str | None = None,
    noise: Noise | None = None,
) -> Path:
    """Write `params` as a model file (atomically), with each parameter's unit, its standard
    error (`stderr`: name -> value), whether it was held fixed (`fixed`: name -> why), the
    correlation of the fitted quantities (names, matrix) and their covariance (names, units,
    matrix; written at full precision, checked positive definite), the `records` it was identified
    from, free `fit` diagnostics, its `noise` in the dynamics, and the package version, git commit and time."""
    stderr, fixed = dict(stderr or {}), dict(fixed or {})
    _check_names(stderr, "stderr")
    _check_names(fixed, "fixed")
    law = LAWS[params.law]

    def entry(key):
        out = {"value": float(getattr(params, key)), "unit": unit_of(key, params.n1)}
        if key in stderr:
            out["stderr"] = _number(stderr[key], f"stderr of {key}")
        if key in fixed:
            out["fixed"] = True
            if fixed[key]:
                out["note"] = str(fixed[key])
        return out

    doc = {"format": FORMAT}
    if name is not None:
        doc["name"] = str(name)
    if law.name != DEFAULT_LAW:  # a file without contact is of the default law, model BC's
        doc["contact"] = {"law": law.name, **{key: entry(key) for key in law.own}}
    doc["parameters"] = {key: entry(key) for key in law.family}
    if noise is not None and noise.active:
        doc["noise"] = noise.to_dict()
    if covariance is not None:
        names, units, matrix = list(covariance[0]), [str(u) for u in covariance[1]], covariance[2]
        if len(units) != len(names):
            raise ValueError(f"covariance: {len(units)} units for {len(names)} names")
        matrix = _spd(matrix, len(names), "covariance to write")
        # repr-exact floats: the matrix read back is the one written
        doc["covariance"] = {"names": [str(n) for n in names], "units": units, "matrix": matrix.tolist()}
    if correlation is not None:
        names, matrix = list(correlation[0]), np.asarray(correlation[1], dtype=float)
        if matrix.shape != (len(names), len(names)):
            raise ValueError(f"correlation: matrix of shape {matrix.shape} for {len(names)} names")
        doc["correlation"] = {"names": [str(n) for n in names], "matrix": matrix.tolist()}
    if records is not None:
        doc["records"] = _plain(list(records))
    if fit is not None:
        doc["fit"] = _plain(dict(fit))
    doc["package_version"] = __version__
    commit = git_commit()
    if commit != "unknown":
        doc["git_commit"] = commit
    doc["created"] = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    text = yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=120, allow_unicode=True)
    path = Path(path)
    with atomic_write(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return path


def _load(path: Path) -> dict:
    """The file's YAML mapping, checked for its format line and known top-level keys."""
    if path.is_dir():
        raise IsADirectoryError(f"model file {path} is a directory, not a file")
    if not path.is_file():
        raise FileNotFoundError(f"model file {path} does not exist")
    try:
        doc = load_yaml(path.read_text(encoding="utf-8"))
    except (DuplicateKeyError, AliasError) as exc:
        raise ValueError(f"model file {path}: {exc}") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"model file {path}: not YAML: {yaml_problem(exc)}") from None
    except UnicodeDecodeError as exc:
        raise ValueError(f"model file {path}: not UTF-8 text (byte {exc.start} cannot be decoded)") from None
    if not isinstance(doc, dict):
        raise ValueError(f"model file {path}: not a model file (a YAML mapping starting with 'format: {FORMAT}')")
    if "format" not in doc:
        raise ValueError(f"model file {path}: format: missing (a model file starts with 'format: {FORMAT}')")
    if doc["format"] != FORMAT:
        raise ValueError(f"model file {path}: format: {shown(doc['format'])} is not {FORMAT!r}")
    for key in doc:
        if key not in _TOP_KEYS:
            raise ValueError(f"model file {path}: {key}: " + _unknown(key, _TOP_KEYS))
    if not isinstance(doc.get("parameters", {}), dict):
        raise ValueError(f"model file {path}: parameters: a mapping of parameter name -> value, not a list or value")
    return doc


def _entry(key: str, entry, path: Path, block: str = "parameters") -> tuple[float, float | None, str | None]:
    """(value, stderr, note-if-fixed) of one parameter, plain number or mapping (its unit is
    checked by :func:`_check_units`, once n1 is known)."""
    where = f"model file {path}: {block}.{key}"
    if not isinstance(entry, dict):
        return _number(entry, where), None, None
    for sub in entry:
        if sub not in _ENTRY_KEYS:
            raise ValueError(f"{where}.{sub}: " + _unknown(sub, _ENTRY_KEYS))
    if "value" not in entry:
        raise ValueError(f"{where}.value: missing (write {key}: {{value: ..., unit: {PARAM_UNITS[key]}}})")
    value = _number(entry["value"], f"{where}.value")
    stderr = _number(entry["stderr"], f"{where}.stderr") if entry.get("stderr") is not None else None
    if stderr is not None and stderr < 0:
        raise ValueError(f"{where}.stderr: {stderr} is negative")
    if not isinstance(entry.get("fixed", False), bool):
        raise ValueError(f"{where}.fixed: {shown(entry['fixed'])} is not true or false")
    note = str(entry.get("note") or "") if entry.get("fixed") else None
    return value, stderr, note


def _check_units(blocks: dict, n1: float, path: Path) -> None:
    """Each stated unit is the parameter's SI unit (kI's follows n1): refused, not converted."""
    for block, entries in blocks.items():
        for key, entry in entries.items():
            unit = entry.get("unit") if isinstance(entry, dict) else None
            if unit is not None and (not isinstance(unit, str) or " ".join(unit.split()) != unit_of(key, n1)):
                raise ValueError(
                    f"model file {path}: {block}.{key}.unit: {shown(unit)}, but {key} is in {unit_of(key, n1)!r} "
                    "(values are SI, not converted)"
                )


def _contact(doc: dict, path: Path) -> tuple[str, dict]:
    """(law name, its own entries) of the ``contact`` block; model BC's without one."""
    block = doc.get("contact")
    if block is None:
        return DEFAULT_LAW, {}
    where = f"model file {path}: contact"
    if not isinstance(block, dict) or "law" not in block:
        raise ValueError(f"{where}: a mapping with the law's name, e.g. contact: {{law: flores, e: 0.7}}")
    try:
        law = law_of(block["law"])
    except ValueError as exc:
        raise ValueError(f"{where}.law: {exc}") from None
    own = {k: v for k, v in block.items() if k != "law"}
    for key in own:
        if key not in law.own:
            raise ValueError(
                f"{where}.{key}: the {law.name} law takes " + (", ".join(law.own) or "nothing") + " beside law"
            )
    missing = [key for key in law.own if key not in own]
    if missing:
        raise ValueError(f"{where}.{missing[0]}: missing: the {law.name} law needs it ({law.force})")
    return law.name, own


def read_model_file(path) -> ModelFile:
    """Read and check a model file; ValueError or FileNotFoundError naming the file and key."""
    path = Path(path)
    doc = _load(path)
    values, stderr, fixed = {}, {}, {}
    law, own = _contact(doc, path)
    given = doc.get("parameters") or {}
    for block, entries in (("parameters", given), ("contact", own)):
        for key, entry in entries.items():
            if block == "parameters" and key not in NAMES:
                absent = [n for n in NAMES if n not in given]
                raise ValueError(f"model file {path}: parameters.{key}: " + _unknown(key, NAMES, "parameter", absent))
            if block == "parameters" and key not in LAWS[law].family:
                raise ValueError(
                    f"model file {path}: parameters.{key}: the {law} law has no {key} (model BC's damping; "
                    f"{LAWS[law].force})"
                )
            values[key], err, note = _entry(key, entry, path, block)
            if err is not None:
                stderr[key] = err
            if note is not None:
                fixed[key] = note
    if LAWS[law].n1 is not None:
        values.setdefault("n1", LAWS[law].n1)  # a law of its own exponent (Kelvin-Voigt's linear: kI in N/m)
    _check_units({"parameters": given, "contact": own}, values.get("n1", ModelParams.n1), path)
    values["law"] = law
    try:
        params = ModelParams(**values)
    except ValueError as exc:
        bad = next((k for k in values if f"parameter {k} " in str(exc)), None)
        raise ValueError(
            f"model file {path}: parameters.{bad}: {exc}" if bad else f"model file {path}: {exc}"
        ) from None
    meta = {k: v for k, v in doc.items() if k not in ("format", "parameters", "contact")}
    _check_covariance(meta.get("covariance"), path)  # here, so a bad block is named when the file is read
    _check_correlation(meta.get("correlation"), path)
    try:
        Noise.from_dict(meta.get("noise"))
    except ValueError as exc:
        raise ValueError(f"model file {path}: {exc}") from None
    defaulted = tuple(k for k in LAWS[law].family if k not in values)
    return ModelFile(params, stderr, fixed, meta, str(path), defaulted)


def _check_names_unique(names, where: str) -> None:
    """Each name of a covariance or correlation once: a name given twice would pair one row with
    two different quantities' uncertainties."""
    twice = sorted({str(n) for n in names if list(names).count(n) > 1})
    if twice:
        raise ValueError(f"{where}.names: {', '.join(twice)} given more than once; each quantity has one row")


def _check_covariance(cov, path: Path) -> None:
    """The covariance block: a mapping of distinct names, as many units as names (when given), a
    symmetric positive definite matrix of their size."""
    if cov is None:
        return
    where = f"model file {path}: covariance"
    if not isinstance(cov, dict) or not isinstance(cov.get("names"), list) or "matrix" not in cov:
        raise ValueError(f"{where}: need a mapping with names and matrix")
    for key in cov:
        if key not in ("names", "units", "matrix"):
            raise ValueError(f"{where}.{key}: " + _unknown(key, ("names", "units", "matrix")))
    _check_names_unique(cov["names"], where)
    units = cov.get("units")
    if units is not None and (not isinstance(units, list) or len(units) != len(cov["names"])):
        count = f"{len(units)} units" if isinstance(units, list) else shown(units)
        raise ValueError(f"{where}.units: {count} for {len(cov['names'])} names; give one unit per name, in order")
    _spd(cov["matrix"], len(cov["names"]), f"model file {path}")


def _check_correlation(corr, path: Path) -> None:
    """The correlation block (for reading): distinct names and a symmetric matrix of their size
    with a unit diagonal and every entry in [-1, 1]."""
    if corr is None:
        return
    where = f"model file {path}: correlation"
    if not isinstance(corr, dict) or not isinstance(corr.get("names"), list) or "matrix" not in corr:
        raise ValueError(f"{where}: need a mapping with names and matrix")
    _check_names_unique(corr["names"], where)
    n = len(corr["names"])
    try:
        a = np.asarray(corr["matrix"], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{where}.matrix: not a table of numbers") from None
    if a.shape != (n, n) or not np.all(np.isfinite(a)):
        raise ValueError(f"{where}.matrix: need a finite {n} x {n} matrix for its {n} names, got shape {a.shape}")
    i, j = np.unravel_index(np.argmax(np.abs(a)), a.shape)
    if abs(a[i, j]) > 1.0:
        raise ValueError(f"{where}.matrix: {a[i, j]:g} at row {i + 1}, column {j + 1}; a correlation lies in [-1, 1]")
    # written rounded for reading (4 digits); a diagonal off 1 or an asymmetry beyond that is no correlation
    if np.any(np.abs(np.diag(a) - 1.0) > 1e-4) or np.any(np.abs(a - a.T) > 1e-4):
        raise ValueError(f"{where}.matrix: a correlation matrix is symmetric with 1 on its diagonal")


def _override(item: str) -> tuple[str, float]:
    """(name, value) of one NAME=VALUE item, errors naming the item."""
    name, text = split_assignment(item)
    if text is None:
        raise ValueError(f"parameter override {shown(item)}: write NAME=VALUE, e.g. k=1500")
    if name not in PARAM_UNITS:
        known = list(PARAM_UNITS)
        raise ValueError(f"parameter override {shown(item)}: " + _unknown(name, known, f"parameter {shown(name)}"))
    return name, _number(text, f"parameter override {shown(item)}")


def apply_overrides(params: ModelParams, items) -> ModelParams:
    """`params` with each ``NAME=VALUE`` of `items` set (later items win)."""
    changes = {}
    law = LAWS[params.law]
    for item in items:
        name, value = _override(item)
        if name not in law.fields:
            raise ValueError(f"parameter override {shown(item)}: the {law.name} law has no {name} ({law.force})")
        try:
            dataclasses.replace(params, **{name: value})
        except ValueError as exc:
            raise ValueError(f"parameter override {shown(item)}: {exc}") from None
        changes[name] = value
    return dataclasses.replace(params, **changes) if changes else params


def resolve_model(file=None, overrides=()) -> tuple[ModelParams, str]:
    """The model a command or the workflow uses, and what it is: model BC, or the model file,
    then the overrides; e.g. ("model file rig.yaml (eps from model BC) + k=1500")."""
    if file is None:
        params, source = ModelParams(), BC_DESCRIPTION
    else:
        model = read_model_file(file)
        params, source = model.params, f"model file {file}"
        if len(model.defaulted) > len(NAMES) // 2:
            given = [k for k in LAWS[model.params.law].family if k not in model.defaulted]  # as ``defaulted``
            source += f" ({', '.join(given) or 'no parameter'}; the rest from model BC)"
        elif model.defaulted:
            source += f" ({', '.join(model.defaulted)} from model BC)"
    overrides = list(overrides)
    if overrides:
        params = apply_overrides(params, overrides)
        source += " + " + ", ".join("=".join(split_assignment(item)) for item in overrides)
    return params, source
