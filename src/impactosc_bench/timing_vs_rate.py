"""Impact-time error against the sample rate on the surrogate: how close extraction comes to its
Cramer-Rao bound, and whether its stated sigma_t holds, at 1-50 kHz.

Why a script beside the noise study: this is the plain check a user would run on the command
line (``impactosc surrogate ... --rate R``, ``impactosc extract``, the exact impacts of the same
simulation), in one process and one table, for any duration, noise and rates.

    python -m impactosc_bench.timing_vs_rate [--rates 1000 2000 ...] [--duration 300] [--noise 5e-6]

Per rate: impacts true / missed / invented, the rms and median |error|, the rms of the per-impact
bound, the rms of error / bound (1: at the bound), the share of errors within 2 stated sigma_t
and the rms of error / sigma_t (0.95 and 1 when sigma_t is honest).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from impactosc.records.extract import ExtractOptions, extract_events
from impactosc.records.impact_times import crossing_time_crb
from impactosc.records.record import Record
from impactosc.records.surrogate import SurrogateOptions, surrogate_record
from impactosc_study.noise_study import match_impacts

__all__ = ["timing_row", "main"]

COLUMNS = [
    ("rate_hz", "rate (Hz)", "{:g}"),
    ("n_true", "true", "{:d}"),
    ("missed", "missed", "{:d}"),
    ("extra", "invented", "{:d}"),
    ("rms_s", "rms error (s)", "{:.3g}"),
    ("median_abs_s", "median abs error (s)", "{:.3g}"),
    ("bound_rms_s", "rms bound (s)", "{:.3g}"),
    ("rms_error_over_bound", "rms error/bound", "{:.3f}"),
    ("within_2sigma", "within 2 sigma_t", "{:.3f}"),
    ("rms_z", "rms error/sigma_t", "{:.3f}"),
    ("sigma_t_median_s", "median sigma_t (s)", "{:.3g}"),
    ("extract_s", "extraction (s)", "{:.2f}"),
]


def timing_row(rate, *, omega=40.86, transient=100.0, duration=300.0, noise=5e-6, seed=1) -> dict:
    """Extract one surrogate record at ``rate`` (x_impact given, white noise of std ``noise``
    drawn from ``seed``) and score its impact times against the exact ones."""
    rec0, truth = surrogate_record(omega, transient, duration, SurrogateOptions(rate=float(rate), noise=0.0))
    x = rec0.x + np.random.default_rng(seed).normal(0.0, noise, rec0.x.size)
    start = time.perf_counter()
    ev, _ = extract_events(Record(rec0.t, x, None, rec0.meta, rec0.path), rec0.meta["x_impact"], ExtractOptions())
    elapsed = time.perf_counter() - start
    T, V = truth["impacts"]["t"], truth["impacts"]["v"]
    imp = ev["impacts"]
    found, true = match_impacts(T, imp["t"])
    err = imp["t"][found] - T[true]
    z = err / imp["sigma_t"][found]
    dt = 1.0 / rate
    n = imp["fit_samples"][found]
    centre = imp["fit_start"][found] + (n - 1) / 2 * dt
    bound = crossing_time_crb(noise, V[true], (T[true] - centre) / dt, n, imp["fit_degree"][found])
    return {
        "rate_hz": float(rate),
        "n_true": int(T.size),
        "missed": int(T.size - true.size),
        "extra": int(imp["t"].size - found.size),
        "rms_s": float(np.sqrt(np.mean(err**2))),
        "median_abs_s": float(np.median(np.abs(err))),
        "bound_rms_s": float(np.sqrt(np.mean(bound**2))),
        "rms_error_over_bound": float(np.sqrt(np.mean((err / bound) ** 2))),
        "within_2sigma": float(np.mean(np.abs(z) < 2)),
        "rms_z": float(np.sqrt(np.mean(z**2))),
        "sigma_t_median_s": float(np.median(imp["sigma_t"])),
        "extract_s": elapsed,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m impactosc_bench.timing_vs_rate",
        description="Impact-time error of extraction against the sample rate, on the surrogate "
        "(x_impact given), scored against the exact impacts and each impact's Cramer-Rao bound.",
    )
    ap.add_argument("--rates", type=float, nargs="+", default=[1e3, 2e3, 5e3, 1e4, 2e4, 5e4], help="Hz")
    ap.add_argument("--omega", type=float, default=40.86, help="rad/s (default: the chaotic scene)")
    ap.add_argument("--transient", type=float, default=100.0, help="s simulated before the record")
    ap.add_argument("--duration", type=float, default=300.0, help="s of record")
    ap.add_argument("--noise", type=float, default=5e-6, help="m, std of the white sensor noise")
    ap.add_argument("--seed", type=int, default=1, help="seed of the noise")
    args = ap.parse_args(argv)
    for name in ("transient", "duration", "noise"):
        if not getattr(args, name) > 0:
            ap.error(f"--{name} must be > 0, got {getattr(args, name)}")
    if not all(r > 0 for r in args.rates):
        ap.error(f"--rates must be > 0 Hz, got {args.rates}")
    print("| " + " | ".join(head for _, head, _ in COLUMNS) + " |")
    print("|" + "---|" * len(COLUMNS))
    for rate in args.rates:
        row = timing_row(
            rate, omega=args.omega, transient=args.transient, duration=args.duration, noise=args.noise, seed=args.seed
        )
        print("| " + " | ".join(fmt.format(row[key]) for key, _, fmt in COLUMNS) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
