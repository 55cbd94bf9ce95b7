"""Noise study: sensor noise and sample rate against the extracted train's statistics.

Reads snakemake.params (study: rates, noise levels, x_impact_span, realism cases; surrogate:
scene, mismatch, seed; analysis: chaotic.analysis options); writes snakemake.output.csv (one
row per rate x noise x extraction method, then one per sensor-realism case) and .json (the
same rows with ISI kernel densities, for the figure).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging
import time

from impactosc.analysis.impact_train import AnalysisOptions
from impactosc.files import write_csv, write_json
from impactosc.integration.model import ModelParams
from impactosc.measured.noise_study import noise_study

p = snakemake.params
c = p.surrogate["chaos"]
t0 = time.perf_counter()
rows = noise_study(
    c["omega"],
    c["transient"],
    c["duration"],
    p.study["rates"],
    p.study["noise"],
    analysis=AnalysisOptions.from_config(p.analysis),
    mismatch=p.surrogate["mismatch"],
    seed=p.surrogate["seed"],
    params=ModelParams(**p.model),
    x_impact_span=p.study.get("x_impact_span", 0.0),
    x_impact_noise=p.study.get("x_impact_noise", []),
    realism=p.study.get("realism", {}).get("cases"),
    realism_noise=p.study.get("realism", {}).get("noise", 5e-6),
    realism_rate=p.study["density_rate"],
    **p.solver,
)
write_json(snakemake.output.json, {"rows": rows})
columns = [
    "rate_hz",
    "noise_m",
    "method",
    "n_true",
    "n_found",
    "missed",
    "extra",
    "timing_rms_s",
    "timing_bias_s",
    "timing_max_z",
    "frac_beyond_5sigma",
    "sigma_t_median_s",
    "timing_err_median_s",
    "timing_crb_median_s",
    "timing_crb_ratio",
    "penetration_bias_m",
    "penetration_err_median_m",
    "x_impact_err_m",
    "x_impact_sigma_m",
    "sensor_delay_s",
    "noise_estimate_m",
    "cv2_paper",
    "cv2",
    "isi_n_modes",
    "isi_maxima",
    "isi_valley_ratio",
    "acf_n_significant",
    "note",
    "x_impact_note",
]
write_csv(snakemake.output.csv, [{k: r.get(k, "") for k in columns} for r in rows])
logging.info(f"{len(rows)} rows in {time.perf_counter() - t0:.1f} s")
