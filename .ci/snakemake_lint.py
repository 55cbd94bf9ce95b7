"""`snakemake --lint`, failing on every lint but one: rules carry no conda or container
directive, because the locked virtual environment (requirements.lock, `make`) is the
supported set-up (README, Dependencies). Usage: python .ci/snakemake_lint.py SNAKEMAKE"""

import re
import subprocess
import sys

ACCEPTED = "Specify a conda environment or container for each rule."

out = subprocess.run([sys.argv[1], "--lint"], capture_output=True, text=True)
text = out.stdout + out.stderr
lints = re.findall(r"^\s+\* (.+?):\s*$", text, flags=re.MULTILINE)
if not lints and out.returncode != 0:
    sys.exit(f"snakemake --lint failed without lints:\n{text}")
others = [lint for lint in lints if lint != ACCEPTED]
if others:
    print(text)
    sys.exit(f"snakemake --lint: {len(others)} lint(s) besides the accepted one ({ACCEPTED!r}): {sorted(set(others))}")
print(f"snakemake --lint: no lints ({len(lints)} rules without conda/container, by design)")
