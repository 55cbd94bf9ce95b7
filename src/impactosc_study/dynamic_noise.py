"""Dynamic-noise study: does noise in the dynamics merge the chaotic scene's two ISI maxima, and
which statistics move first?

Why a module of its own: the paper blames noise for its rig's weakly bimodal ISI histogram (after
Sauer 1995). Sensor noise on x does not merge the maxima (:mod:`impactosc_study.noise_study`); this
study drives the model itself with each noise of :mod:`impactosc.model.noise` (the motor's speed
jitter, a random force on the cart) at a ladder of intensities, an ensemble of seeds per level, and
scores every train with the statistics of :func:`impactosc.statistics.train_analysis.analyse_train`.

The ISI maxima count as merged at a level when the density of the ensemble's pooled intervals has
one maximum (the same kernel density and prominence rule as the paper's Fig 9). A workflow runs
:func:`noise_ladder` once per noise (a job each) and :func:`summary` on their rows.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from impactosc.core.simulation import simulate
from impactosc.model.noise import PROCESSES, Noise, NoiseProcess
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain
from impactosc.statistics.train_analysis import analyse_train, key_numbers

__all__ = ["COLUMNS", "noise_ladder", "summary"]

#: Columns of the study's table, one row per (noise, level): ensemble means and spreads
COLUMNS = [
    "noise",
    "rms",
    "unit",
    "tau_s",
    "members",
    "n_impacts",
    "pooled_n_maxima",
    "pooled_maxima_s",
    "pooled_valley_ratio",
    "members_bimodal",
    "cv2_paper",
    "cv2_paper_sd",
    "cv2",
    "holt_cv2",
    "lv",
    "lvr",
    "serial_correlation_1",
    "serial_correlation_1_sd",
    "acf_peak_frequency",
    "acf_second_frequency",
    "acf_n_significant",
    "penetration_n_modes",
    "wall_time_s",
]
PARTS = ("variability", "isi_density", "acf", "penetrations", "local_variability")
_MEANS = ("n_impacts", "cv2_paper", "cv2", "holt_cv2", "lv", "lvr", "serial_correlation_1", "acf_n_significant")


def _valley(grid, dens, maxima) -> float:
    """Density minimum between the outer maxima over the lower of them (1: no dip; nan: one maximum)."""
    if len(maxima) < 2:
        return float("nan")
    inside = (grid > maxima[0]) & (grid < maxima[-1])
    low = min(np.interp(maxima[0], grid, dens), np.interp(maxima[-1], grid, dens))
    return float(dens[inside].min() / low)


def _member(omega, transient, duration, params, noise, solver, options) -> tuple[dict, np.ndarray]:
    """Key numbers of one noisy run and its ISIs."""
    res = simulate(omega, transient, duration, params=params, noise=noise, record=("impacts", "penetrations"), **solver)
    pen = res.events["penetrations"]
    train = ImpactTrain(res.impact_times, transient, transient + duration, omega=omega, penetrations=pen["h"])
    numbers = key_numbers(analyse_train(train, options, PARTS))
    numbers["wall_time"] = res.attrs["wall_time"]
    return numbers, train.intervals


def noise_ladder(
    name: str,
    levels,
    *,
    tau: float,
    seeds: int,
    omega: float,
    transient: float,
    duration: float,
    params: ModelParams,
    solver: dict,
    options: AnalysisOptions,
    progress: Callable[[str], None] = lambda _: None,
) -> tuple[list[dict], dict]:
    """Rows (COLUMNS) of one noise (a key of PROCESSES) at each rms of `levels`, and the pooled ISI
    densities by level ({rms: (grid, density)}) for the figure. Level 0 is the noise-free run (one
    member: every seed gives the same run)."""
    if name not in PROCESSES:
        raise ValueError(f"unknown noise {name!r}; choose from {list(PROCESSES)}")
    rows, densities = [], {}
    for rms in levels:
        t0 = time.perf_counter()
        members, pooled = [], []
        for seed in range(1 if rms == 0 else seeds):
            noise = Noise(seed=seed, **{name: NoiseProcess(float(rms), float(tau))})
            numbers, isi = _member(omega, transient, duration, params, noise, solver, options)
            members.append(numbers)
            pooled.append(isi)
        dens = analyse_train(_pooled_train(pooled, omega), options, ("isi_density",))["isi_density"]
        grid, density = np.asarray(dens["kde_grid"]), np.asarray(dens["kde_density"])
        maxima = np.asarray(dens["maxima"], dtype=float)
        densities[float(rms)] = (grid, density)
        row = {
            "noise": name,
            "rms": float(rms),
            "unit": PROCESSES[name][0],
            "tau_s": float(tau),
            "members": len(members),
            "pooled_n_maxima": int(maxima.size),
            "pooled_maxima_s": " ".join(f"{m:.4f}" for m in maxima),
            "pooled_valley_ratio": _valley(grid, density, maxima),
            "members_bimodal": sum(m["isi_n_maxima"] >= 2 for m in members),
            "cv2_paper_sd": float(np.std([m["cv2_paper"] for m in members], ddof=1)) if len(members) > 1 else 0.0,
            "serial_correlation_1_sd": (
                float(np.std([m["serial_correlation_1"] for m in members], ddof=1)) if len(members) > 1 else 0.0
            ),
            "acf_peak_frequency": _mean(m["acf_peak_frequency"] for m in members),
            "acf_second_frequency": _mean(m["acf_second_frequency"] for m in members),
            "penetration_n_modes": _mean(m.get("penetration_n_modes") for m in members),
            "wall_time_s": time.perf_counter() - t0,
        }
        row.update({k: _mean(m[k] for m in members) for k in _MEANS})
        rows.append(row)
        progress(
            f"{name} rms {rms:g} {row['unit']}: {row['members']} members, pooled ISI maxima {row['pooled_maxima_s']} s, "
            f"C_V^2 {row['cv2_paper']:.4f} s, r(1) {row['serial_correlation_1']:+.3f} ({row['wall_time_s']:.1f} s)"
        )
    return rows, densities


def _pooled_train(intervals: list[np.ndarray], omega: float) -> ImpactTrain:
    """One train whose intervals are all the members' (their order does not matter to the density)."""
    times = np.concatenate([[0.0], np.cumsum(np.concatenate(intervals))])
    return ImpactTrain(times, 0.0, float(times[-1]), omega=omega)


def _mean(values) -> float:
    vals = [v for v in values if v is not None]
    return float(np.mean(vals)) if vals else float("nan")


def summary(rows: list[dict]) -> dict:
    """Per noise: the smallest rms whose pooled ISI density has one maximum (None: bimodal at every
    level tried), the largest tried, and how far each statistic moved there from the noise-free run."""
    out = {}
    for name in dict.fromkeys(r["noise"] for r in rows):
        ladder = sorted((r for r in rows if r["noise"] == name), key=lambda r: r["rms"])
        base = ladder[0]
        merged = next((r for r in ladder if r["pooled_n_maxima"] < 2), None)
        top = ladder[-1]
        first = {}
        for key in (
            "penetration_n_modes",
            "cv2_paper",
            "lv",
            "serial_correlation_1",
            "acf_peak_frequency",
            "n_impacts",
        ):
            # the first level at which the statistic left the noise-free value by 10 % (relative; absolute for r(1))
            scale = 1.0 if key == "serial_correlation_1" else abs(base[key]) or 1.0
            moved = next((r for r in ladder[1:] if abs(r[key] - base[key]) / scale > 0.1), None)
            first[key] = None if moved is None else moved["rms"]
        out[name] = {
            "unit": base["unit"],
            "tau_s": ladder[-1]["tau_s"],
            "merge_rms": None if merged is None else merged["rms"],
            "largest_rms": top["rms"],
            "moved_10_percent_at": first,
            "at_largest": {
                k: (base[k], top[k])
                for k in ("cv2_paper", "lv", "serial_correlation_1", "penetration_n_modes", "n_impacts")
            },
            "maxima_s": {f"{r['rms']:g}": r["pooled_maxima_s"] for r in ladder},
        }
    return out
