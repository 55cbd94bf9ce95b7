"""Regenerate tests/data/law_impacts_before_components.json: each contact law's impact times.

Run from the repository root of the revision whose core is the reference (these values were
made by the revision before the contact laws became components, where each law's cut was
located by code of its own):  .venv/bin/python tests/data/make_law_impacts_reference.py

The scene: the chaotic scene's forcing (w = 40.86 rad/s) from rest, simulate's default
tolerances, the impacts of the first 1.5 s. Why so short: the motion from rest is sensitive to
the last bits of the core (measured: one rounding of a restitution law's chi grew to 1.5e-11 s
within one bounce), so only the first impacts compare at 1e-12 s.
"""

import json
import warnings
from pathlib import Path

from impactosc.core.simulation import simulate
from impactosc.model.parameters import ModelParams

OMEGA, HORIZON = 40.86, 1.5
LAWS = {
    "hertz": dict(law="hertz"),
    "kelvin-voigt": dict(law="kelvin-voigt", n1=1.0, kI=2e6, cI=300.0),
    "hunt-crossley": dict(law="hunt-crossley", e=0.6),
    "lankarani-nikravesh": dict(law="lankarani-nikravesh", e=0.6),
    "flores": dict(law="flores", e=0.6),
    "gonthier": dict(law="gonthier", e=0.6),
}

if __name__ == "__main__":
    out = {
        "about": __doc__.split("\n\n")[0],
        "omega": OMEGA,
        "horizon": HORIZON,
        "laws": {},
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, kw in LAWS.items():
            t = simulate(OMEGA, 0.0, HORIZON, params=ModelParams(**kw), record=("impacts",)).events["impacts"]["t"]
            out["laws"][name] = {"params": kw, "impacts_t": [float(x) for x in t]}
    path = Path(__file__).with_name("law_impacts_before_components.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")
