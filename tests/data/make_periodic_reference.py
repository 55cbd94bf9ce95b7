"""Write tests/data/periodic_reference.json: the periodic-regime and grazing regression references.

Run from the repository root: .venv/bin/python tests/data/make_periodic_reference.py [--full]
The short scenes are those of tests/test_periodic_regression.py (shared through
impactosc.statistics.periodic_train / impactosc.dynamics.grazing, so the test and this script compute the same thing);
--full also stores the full branch from w = 40.86 (about 40 s) for the slow test.
"""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from test_periodic_regression import full_branch, period4_short, short_branch

from impactosc.io.files import git_commit

out = Path(__file__).with_name("periodic_reference.json")
ref = json.loads(out.read_text()) if out.exists() else {}
ref["period4"] = period4_short()
ref["short_branch"] = short_branch()
if "--full" in sys.argv:
    ref["full_branch"] = full_branch()
ref["written_by"] = f"tests/data/make_periodic_reference.py {' '.join(sys.argv[1:])} at commit {git_commit()}"
out.write_text(json.dumps(ref, indent=1) + "\n")
print(json.dumps(ref, indent=1))
