"""Write tests/data/bifurcation_reference.json: the reference of tests/test_sweep_regression.py.

Run from the repository root: .venv/bin/python tests/data/make_bifurcation_reference.py
(about 5 s). The test and this script share cascade_reading(), so they compute the same thing.
"""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from test_sweep_regression import cascade_reading

from impactosc.io.files import git_commit

out = Path(__file__).with_name("bifurcation_reference.json")
ref = {"cascade": cascade_reading(), "written_by": f"tests/data/make_bifurcation_reference.py at commit {git_commit()}"}
out.write_text(json.dumps(ref, indent=1) + "\n")
print(json.dumps(ref, indent=1))
