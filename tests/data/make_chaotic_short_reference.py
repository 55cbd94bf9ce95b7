"""Regenerate tests/data/chaotic_short_reference.json (regression values of the short chaos scene).

Run from the repository root:  .venv/bin/python tests/data/make_chaotic_short_reference.py

The short scene is the paper's chaos scene cut to 100 s of record (w = 40.86, from rest,
100 s transient, rtol 1e-10).  A chaotic trajectory is bit-reproducible only on the same
platform and compiler; elsewhere it decorrelates after a few seconds and only its statistics
survive.  So besides the reference values this script stores their spread over
independent 100 s realisations of the same attractor (other initial states), which the test
uses as tolerance scale.
"""

import json
import platform
import sys
from pathlib import Path

import numpy as np

from impactosc import __version__
from impactosc.core.simulation import simulate
from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain
from impactosc.statistics.train_analysis import analyse_train, key_numbers

OMEGA, TRANSIENT, DURATION = 40.86, 100.0, 100.0
#: Statistics compared by the test (scalars of key_numbers).
KEYS = (
    "n_impacts",
    "cv2_paper",
    "cv2",
    "isi_first_maximum",
    "isi_last_maximum",
    "acf_peak_frequency",
    "penetration_n_modes",
)
#: Fast options: the regression test must stay well under a few seconds.
OPTIONS = dict(mixture_components=[1, 2], mixture_restarts=4, ks_bootstrap=199, acf_surrogates=100)
REALISATION_X0 = (1e-4, 2e-4, 5e-4, -5e-4, 1e-3, -1e-3, 2e-3, 3e-3)


def short_scene_stats(x0=0.0):
    res = simulate(OMEGA, TRANSIENT, DURATION, x0=x0, record=("impacts", "penetrations"))
    train = ImpactTrain(
        res.events["impacts"]["t"],
        TRANSIENT,
        TRANSIENT + DURATION,
        penetrations=res.events["penetrations"]["h"],
        omega=OMEGA,
        label="short",
    )
    return analyse_train(train, AnalysisOptions(**OPTIONS))


def main():
    ref = short_scene_stats()
    spread = {k: [] for k in KEYS}
    for x0 in REALISATION_X0:
        k = key_numbers(short_scene_stats(x0))
        for name in KEYS:
            spread[name].append(k[name])
    ref_k = key_numbers(ref)
    out = {
        "description": __doc__.strip().splitlines()[0],
        "command": ".venv/bin/python tests/data/make_chaotic_short_reference.py",
        "scene": {"omega": OMEGA, "transient": TRANSIENT, "duration": DURATION, "x0": 0.0, "rtol": 1e-10},
        "options": OPTIONS,
        "generated_with": {"impactosc": __version__, "python": sys.version.split()[0], "machine": platform.machine()},
        "reference": {k: ref_k[k] for k in KEYS}
        | {
            "equal_rate_rejected": ref["stationarity"]["rejected"],
            "ks_rejected": ref["poisson"]["rejected"],
            "mixture_best_2": ref_k["mixture_best_2"],
            "isi_n_maxima": ref_k["isi_n_maxima"],
        },
        "realisations": {
            "x0": list(REALISATION_X0),
            "values": spread,
            "sd": {k: float(np.std(v, ddof=1)) for k, v in spread.items()},
        },
    }
    path = Path(__file__).with_name("chaotic_short_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out["reference"], indent=1), json.dumps(out["realisations"]["sd"], indent=1))


if __name__ == "__main__":
    main()
