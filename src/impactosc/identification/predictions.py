"""Predictions of an identified model with error bars: its located bifurcation points on the
period-1 branch, each with the standard error the model's covariance gives it.

Why here: the model file states the covariance of the quantities identification fits (per unit
mass: k/m, c/m, ...); the points' sensitivities are to the model's own parameters (k, c, ...).
This module turns the one into the other and runs the branch, the location and the delta method
(:mod:`impactosc.dynamics.point_sensitivity`) for a model file.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from impactosc.identification.fitted_parameters import ALL_FIELDS, PER_MASS, QUANTITIES, quantity_unit
from impactosc.model.model_file import ModelFile
from impactosc.model.parameters import PARAM_UNITS, ModelParams

__all__ = [
    "branch_band",
    "covariance_source",
    "field_covariance",
    "point_errors",
    "points_markdown",
    "predicted_points",
    "relocated_point",
    "check_row",
]


def field_covariance(model: ModelFile) -> tuple[list[str], np.ndarray] | None:
    """The model file's covariance in the model's parameters (k, c, ...), or None when the file
    states no uncertainty (model BC's).

    The file's covariance may name the quantities identification fits (per unit mass: a k/m row
    and column times the mass gives k's) or the parameters themselves, each in its own unit; a file
    with each parameter's ``stderr`` and no covariance states independent errors (a diagonal
    covariance, :func:`covariance_source` says so)."""
    found = model.covariance
    if found is None:
        stated = {name: se for name, se in model.stderr.items() if se > 0}
        if not stated:
            return None
        return list(stated), np.diag(np.square(list(stated.values())))
    names, units, cov = found
    fields, scale = [], []
    for i, name in enumerate(names):
        if name in QUANTITIES:
            j = QUANTITIES.index(name)
            field, factor = ALL_FIELDS[j], model.params.m if PER_MASS[j] else 1.0
            unit = quantity_unit(name, model.params.n1)
        elif name in PARAM_UNITS:
            field, factor, unit = name, 1.0, PARAM_UNITS[name]
        else:
            raise ValueError(
                f"{model.path}: covariance names {name!r}: neither a quantity identification fits ({', '.join(QUANTITIES)}) "
                f"nor a parameter ({', '.join(PARAM_UNITS)})"
            )
        if units and " ".join(str(units[i]).split()) != unit:
            raise ValueError(
                f"{model.path}: covariance: {name} is in {unit!r}, not {units[i]!r} (units are not converted)"
            )
        if field in fields:
            raise ValueError(f"{model.path}: covariance: {name} and another name both stand for {field}")
        fields.append(field)
        scale.append(factor)
    return fields, cov * np.outer(scale, scale)


def covariance_source(model: ModelFile) -> str:
    """Where the uncertainty :func:`field_covariance` propagates comes from, in words."""
    if model.covariance is not None:
        return "the model file's covariance"
    if any(se > 0 for se in model.stderr.values()):
        return "the parameters' stderr, as independent errors (the model file states no covariance)"
    return "none (the model file states no covariance and no stderr)"


def read_model_with_covariance(path) -> tuple[ModelFile, tuple[list[str], np.ndarray]]:
    """The model file at ``path`` and its covariance in the model's parameters
    (:func:`field_covariance`); a ValueError naming the file when it states no uncertainty."""
    from impactosc.model.model_file import read_model_file

    model = read_model_file(path)
    covariance = field_covariance(model)
    if covariance is None:
        raise ValueError(
            f"{path}: the model file states no covariance and no stderr: there is no uncertainty to propagate"
        )
    if model.covariance is None:
        print(f"{path}: uncertainty from {covariance_source(model)}", file=sys.stderr)
    return model, covariance


def _orbit_of(point: dict, params: ModelParams):
    """The orbit to differentiate at: the located one (a fold's state as located, its monodromy
    at it); for a grazing, 1e-3 rad/s into its near-miss side (the neighbour with fewer impacts;
    a gap of some 0.1 um there), shot with difference steps well inside that gap."""
    from impactosc.dynamics.shooting import SCALE, PeriodicOrbit, monodromy, shoot

    if point["kind"] == "fold":  # not locally unique, so no Newton: the located state as it is
        y = np.array([point["x0"], point["v0"]])
        image, M = monodromy(y, point["omega"], point["n_periods"], params)
        mu = np.linalg.eigvals(M).astype(complex)
        residual = float(np.max(np.abs(image - y) / SCALE))
        return PeriodicOrbit(point["omega"], point["n_periods"], *y, M, mu[np.argsort(-np.abs(mu))], residual, 0)
    w, step = point["omega"], {}
    if point["kind"] == "grazing":
        before, after = point["impacts"]
        toward = point["w_after"] if after < before else point["w_before"]
        w += math.copysign(1e-3, toward - w)
        step = {"step": 1e-6}
    return shoot([point["x0"], point["v0"]], w, point["n_periods"], params, **step)


def predicted_points(
    params: ModelParams,
    covariance: tuple[list[str], np.ndarray] | None = None,
    *,
    w_range=(19.0, 45.0),
    seed_omega: float = 30.0,
    ds: float = 0.05,
    max_points: int = 4000,
    max_period: int = 1,
    progress=None,
) -> list[dict]:
    """The grazings, period doublings and folds of the period-1 branch (seeded from rest at
    ``seed_omega``, continued over ``w_range``) and, up to orbits of ``max_period`` forcing
    periods, of the doubled branches born at its located doublings (and theirs): each with its
    ``segment``, ``se`` (rad/s; nan without a covariance) and its sensitivity to each parameter
    the covariance names (``d_<field>``)."""
    from impactosc.dynamics.branch_segments import seed_from_rest, trace_segment

    lo, hi = (float(w) for w in w_range)
    if not (0 < lo < seed_omega < hi):
        raise ValueError(f"need 0 < w_range[0] < seed_omega < w_range[1], got {lo}, {seed_omega}, {hi}")
    if int(max_period) < 1:
        raise ValueError(f"max_period must be >= 1, got {max_period}")
    say = progress or (lambda message: None)
    say(f"period-1 orbit at w = {seed_omega} from rest")
    options = {"ds": ds, "w_range": (lo, hi), "max_points": max_points, "params": params, "log": say}
    segment = trace_segment(seed=seed_from_rest(seed_omega, 1, params), **options)
    rows = [
        {"segment": "period 1", **r} for r in point_errors(segment["special_points"], params, covariance, progress=say)
    ]
    parents = [segment]
    while parents:
        parent = parents.pop(0)
        if 2 * parent["n_periods"] > int(max_period):
            continue
        for point in parent["special_points"]:
            if point["kind"] != "period_doubling" or not point["located"]:
                continue
            name = f"period {2 * parent['n_periods']} from w = {point['omega']:.4f}"
            say(f"{name}: the doubled branch")
            child = trace_segment(parent_doubling=point, **options)
            found = point_errors(child["special_points"], params, covariance, progress=say)
            rows += [{"segment": name, **r} for r in found]
            parents.append(child)
    return rows


def point_errors(points: list[dict], params: ModelParams, covariance, *, progress=None) -> list[dict]:
    """Each located point of a branch segment (its ``special_points``) with ``se`` (rad/s; nan
    without a covariance, or where the point has no sensitivity, e.g. a fold) and ``d_<field>``."""
    from impactosc.dynamics.point_sensitivity import delta_method_se, point_sensitivities
    from impactosc.dynamics.shooting import ShootingError

    say = progress or (lambda message: None)
    fields, cov = covariance if covariance is not None else ([], None)
    rows = []
    for point in points:
        row = {"kind": point["kind"], "omega": point["omega"], "n_periods": point["n_periods"]}
        if not point["located"]:
            rows.append({**row, "se": math.nan, "note": f"not located: {point.get('why', '')}"})
            continue
        if cov is None:
            rows.append({**row, "se": math.nan, "note": "no covariance in the model"})
            continue
        say(f"{point['kind']} at w = {point['omega']:.8f}: sensitivities")
        try:
            orbit = _orbit_of(point, params)
            sens = point_sensitivities(point["kind"], point["omega"], orbit, params, fields=tuple(fields))
        except (ShootingError, ValueError) as exc:  # e.g. a fold, where the orbit is not locally unique
            rows.append({**row, "se": math.nan, "note": f"no sensitivity: {exc}"})
            continue
        rows.append(
            {**row, "se": delta_method_se(sens, fields, cov), "note": "", **{f"d_{f}": sens[f] for f in fields}}
        )
    return rows


def relocated_point(
    point: dict, params: ModelParams, covariance, draws: int, *, seed: int = 0, sensitivities: dict | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The Monte Carlo check of a located point's standard error: the point (an entry of a
    segment's ``special_points``) relocated for each of ``draws`` parameter sets drawn from the
    covariance (nan where it was not found, e.g. it left the branch), and the delta method's
    prediction for each draw."""
    from impactosc.dynamics.point_sensitivity import relocated_draws

    fields, cov = covariance
    orbit = _orbit_of(point, params)
    return relocated_draws(
        point["kind"], point["omega"], orbit, params, fields, cov, int(draws), seed=seed, sensitivities=sensitivities,
        with_linear=True,
    )  # fmt: skip


def check_row(row: dict, relocated, others: list[dict], *, linear=None, agree: float = 0.15, near: float = 5.0) -> dict:
    """One row of the Monte Carlo check: the point's delta-method ``se`` against the spread of
    its ``relocated`` draws, a verdict (the two agree within ``agree``, relative), the spread's own
    sampling error, how far the relocated points lie from the delta method's ``linear``
    prediction of each draw (rms, in se: ~0 where the spread differs by sampling alone), and the
    other located points of its branch within ``near`` standard errors (near a codimension-2
    point or a fold the point is not linear in the parameters over its uncertainty)."""
    w = np.asarray(relocated, dtype=float)
    ok = np.isfinite(w)
    found = w[ok]
    spread = float(np.std(found, ddof=1)) if found.size > 1 else math.nan
    se = row["se"]
    ratio = spread / se if se > 0 else math.nan
    close = [
        f"{o['kind'].replace('_', ' ')} at w = {o['omega']:.4f} ({abs(o['omega'] - row['omega']) / se:.1f} se)"
        for o in others
        if o is not row and math.isfinite(se) and abs(o["omega"] - row["omega"]) <= near * se
    ]
    verdict = "agree" if abs(ratio - 1.0) <= agree else "DISAGREE"
    missing = w.size - found.size
    notes = close + ([f"{missing} draws not relocated (the point left the branch)"] if missing else [])
    return {
        "kind": row["kind"],
        "omega": row["omega"],
        "se_delta": se,
        "spread_monte_carlo": spread,
        "ratio": ratio,
        "spread_sampling_error": 1.0 / math.sqrt(2 * (found.size - 1)) if found.size > 1 else math.nan,
        "nonlinearity_in_se": (
            float(np.sqrt(np.mean(((found - np.asarray(linear, dtype=float)[ok]) / se) ** 2)))
            if linear is not None and found.size and se > 0
            else math.nan
        ),
        "mean_shift_in_se": float((np.mean(found) - row["omega"]) / se) if found.size and se > 0 else math.nan,
        "draws": int(w.size),
        "relocated": int(found.size),
        "verdict": verdict,
        "near": "; ".join(notes),
    }


def branch_band(segment: dict, params: ModelParams, covariance, *, max_points: int = 100, progress=None) -> dict:
    """The band of a branch segment (as :func:`impactosc.dynamics.branch_segments.trace_segment`
    returns it): at up to ``max_points`` of its sampled orbits, evenly spread along the branch,
    the Poincare points and inter-impact intervals with their standard errors (nan where an
    orbit cannot be differentiated, e.g. at a grazing)."""
    from impactosc.dynamics.orbit_sensitivity import band_standard_errors, orbit_sensitivities
    from impactosc.dynamics.shooting import ShootingError, shoot

    fields, cov = covariance
    samples = segment["points"]
    chosen = np.unique(np.linspace(0, len(samples) - 1, min(int(max_points), len(samples))).round().astype(int))
    band = {"omega": [], "stable": [], "poincare_x": [], "se_poincare_x": [], "isis": [], "se_isis": []}
    for count, i in enumerate(chosen if samples else []):
        sample = samples[i]
        if progress and count % 20 == 0:
            progress(f"band: orbit {count + 1} of {chosen.size}, w = {sample['omega']:.4f}")
        try:
            orbit = shoot([sample["x0"], sample["v0"]], sample["omega"], segment["n_periods"], params)
            se = band_standard_errors(orbit_sensitivities(orbit, params, tuple(fields)), fields, cov)
        except (ShootingError, np.linalg.LinAlgError):  # e.g. at a fold: I - M singular
            se = {
                "poincare_x": np.full(len(sample["poincare_x"]), np.nan),
                "isis": np.full(len(sample["isis"]), np.nan),
            }
        band["omega"].append(sample["omega"])
        band["stable"].append(bool(sample["stable"]))
        for q in ("poincare_x", "isis"):
            band[q].append(list(sample[q]))
            band[f"se_{q}"].append([float(v) for v in se[q]])
    return band


def curve_band(curve: dict, params: ModelParams, covariance, *, max_points: int = 25, progress=None) -> dict:
    """The band of a two-parameter curve (as :func:`impactosc.dynamics.two_parameter.curve_record`
    writes it): at up to ``max_points`` of its points, evenly spread, the standard error of w* at
    that value of the curve's parameter, from the covariance of the model's other parameters (the
    curve's own parameter is its axis); nan where the point cannot be differentiated."""
    from impactosc.dynamics.curve_sensitivity import curve_point_sensitivities
    from impactosc.dynamics.point_sensitivity import delta_method_se
    from impactosc.dynamics.shooting import ShootingError
    from impactosc.dynamics.two_parameter import CurveProblem

    fields, cov = covariance
    keep = [i for i, f in enumerate(fields) if f != curve["parameter"]]
    others, sub = [fields[i] for i in keep], np.asarray(cov)[np.ix_(keep, keep)]
    problem = CurveProblem(curve["kind"], curve["parameter"], curve["n_periods"], params)
    points = curve["points"]
    chosen = np.unique(np.linspace(0, len(points) - 1, min(int(max_points), len(points))).round().astype(int))
    band = {"omega": [], "value": [], "se": []}
    for count, i in enumerate(chosen if points else []):
        point = points[i]
        if progress and count % 5 == 0:
            progress(f"curve band: point {count + 1} of {chosen.size}, w = {point['omega']:.4f}")
        try:
            se = delta_method_se(curve_point_sensitivities(problem, point, tuple(others)), others, sub)
        except (ShootingError, np.linalg.LinAlgError, ValueError):  # e.g. a stencil across a kink
            se = math.nan
        band["omega"].append(point["omega"])
        band["value"].append(point["value"])
        band["se"].append(se)
    return band


def points_markdown(rows, *, title: str, description: str) -> str:
    """The located points with their standard errors as a Markdown table (with the segment of
    each where the rows name theirs)."""
    segments = any("segment" in r for r in rows)
    lines = [
        f"# {title}",
        "",
        description,
        "",
        ("| segment " if segments else "")
        + "| point | w (rad/s) | standard error (rad/s) | w - 2 se | w + 2 se | note |",
        ("|---" if segments else "") + "|---|---|---|---|---|---|",
    ]
    for r in rows:
        se = math.nan if r["se"] is None else r["se"]  # rows read from JSON: a missing se is null
        band = f"{se:.3g} | {r['omega'] - 2 * se:.6f} | {r['omega'] + 2 * se:.6f}" if math.isfinite(se) else " | | "
        first = f"| {r.get('segment', '')} " if segments else ""
        lines.append(f"{first}| {r['kind'].replace('_', ' ')} | {r['omega']:.8f} | {band} | {r['note']} |")
    return "\n".join(lines) + "\n"
