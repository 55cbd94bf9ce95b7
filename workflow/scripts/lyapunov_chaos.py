"""Merge the chaotic spectrum's realisations and checks: statistics, table and figure.

Reads input.runs (lyapunov_members files) and input.checks; writes output.stats (JSON), output.table
(Markdown), output.png, output.pdf (the convergence figure).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("lyapunov_chaos")
configure_logging(snakemake)

import logging

import numpy as np

from impactosc.dynamics.lyapunov import kaplan_yorke
from impactosc.io.files import read_json, write_json, write_text
from impactosc_study.figures import save_figure
from impactosc_study.figures.lyapunov import convergence_figure


def main(inp, out):
    runs = [read_json(p) for p in inp.runs]
    checks = read_json(inp.checks)
    per_period = np.array([r["exponents_per_period"] for r in runs])
    per_second = np.array([r["exponents_per_second"] for r in runs])
    ky = np.array([r["kaplan_yorke"] for r in runs])
    spread = per_second.std(axis=0, ddof=1) if len(runs) > 1 else np.zeros(2)
    stats = {
        "omega": runs[0]["omega"],
        "realisations": len(runs),
        "periods_per_realisation": runs[0]["n_periods"],
        "exponents_per_period_mean": per_period.mean(axis=0),
        "exponents_per_period_std": per_period.std(axis=0, ddof=1) if len(runs) > 1 else np.zeros(2),
        "exponents_per_second_mean": per_second.mean(axis=0),
        "exponents_per_second_std": spread,
        "kaplan_yorke_mean": float(ky.mean()),
        "kaplan_yorke_std": float(ky.std(ddof=1)) if len(runs) > 1 else 0.0,
        "kaplan_yorke_of_mean": kaplan_yorke(per_period.mean(axis=0)),
        "checks": checks["checks"],
        "identity": checks["identity"],
        "cpu_seconds_per_realisation": [r["cpu_seconds"] for r in runs],
    }
    write_json(out.stats, stats, sources=[*inp.runs, inp.checks])
    idt = checks["identity"]
    lines = [
        f"# Lyapunov exponents of the stroboscopic map at w = {stats['omega']} rad/s",
        "",
        f"{len(runs)} realisations of {runs[0]['n_periods']} forcing periods each (after {runs[0]['transient']} s); "
        "uncertainty: the standard deviation over realisations.",
        "",
        "| quantity | per forcing period | per second |",
        "|---|---|---|",
    ]
    lines += [
        f"| lambda{i + 1} | {per_period[:, i].mean():.4f} +- {stats['exponents_per_period_std'][i]:.4f} "
        f"| {per_second[:, i].mean():.4f} +- {spread[i]:.4f} |"
        for i in range(2)
    ]
    lines += [
        f"| Kaplan-Yorke dimension | {ky.mean():.4f} +- {stats['kaplan_yorke_std']:.4f} | |",
        "",
        "| realisation x0 (m) | lambda1 per period | lambda2 per period | Kaplan-Yorke | CPU s |",
        "|---|---|---|---|---|",
        *[f"| {r['x0']:g} | {r['exponents_per_period'][0]:.4f} | {r['exponents_per_period'][1]:.4f} "
          f"| {r['kaplan_yorke']:.4f} | {r['cpu_seconds']:.1f} |" for r in runs],
        "",
        f"Tangent numerics on the same {checks['check_points']} Poincare points (reference rtol "
        f"{checks['reference']['rtol']:g}, step {checks['reference']['step']:g}: "
        f"{checks['reference']['exponents'][0]:.6f}, {checks['reference']['exponents'][1]:.6f}):",
        "",
        "| rtol | step | lambda1 - reference | lambda2 - reference |",
        "|---|---|---|---|",
        *[f"| {c['rtol']:g} | {c['step']:g} | {c['difference'][0]:+.2e} | {c['difference'][1]:+.2e} |"
          for c in checks["checks"]],
        "",
        f"Sum of the exponents against the divergence of the vector field over the first {idt['periods']} periods: "
        f"mean log det J (core, differences) {idt['sum_of_exponents_per_period']:.8f}, mean integral of the "
        f"divergence (variational equations, SciPy) {idt['mean_divergence_per_period']:.8f} per period; difference "
        f"{idt['difference_per_period']:+.2e}, largest single period {idt['largest_single_period_difference']:.2e}.",
        "",
    ]  # fmt: skip
    write_text(out.table, "\n".join(lines))
    fig = convergence_figure(runs, stats["exponents_per_second_mean"], spread)
    save_figure(fig, out.png, out.pdf)
    logging.info("lambda = %s +- %s per second, KY %.4f", per_second.mean(axis=0), spread, ky.mean())


main(snakemake.input, snakemake.output)
