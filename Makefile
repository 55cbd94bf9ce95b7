# Two commands do everything on a fresh machine with Python 3.11:
#   make        install into .venv and run the full workflow (snakemake -j2)
#   make test   install into .venv and run the default (fast) tests, lint and format checks
# Both install the exact versions of requirements.lock (hash-checked); `make lock` refreshes it.
PYTHON ?= python3
LOCK := requirements.lock
VENV := .venv
BIN := $(VENV)/bin
JOBS ?= 2

.PHONY: all install lock test test-slow report lint format check-cluster check-slurm clean

all: install
	$(BIN)/snakemake -j$(JOBS)

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

# The tested environment: every package pinned with its hashes (extras test, peers and slurm),
# then the package itself, built by the locked setuptools (no unpinned build environment).
$(VENV)/.installed: $(BIN)/python $(LOCK) pyproject.toml
	$(BIN)/python -m pip install --quiet --require-hashes --no-deps -r $(LOCK)
	$(BIN)/python -m pip install --quiet --no-deps --no-build-isolation -e .
	touch $@

install: $(VENV)/.installed

# Refresh the lock after changing pyproject's dependencies (uv resolves for every platform
# from PyPI; uv is only the locking tool, not a dependency of the package).
lock: $(BIN)/python
	$(BIN)/python -m pip install --quiet uv
	$(BIN)/uv pip compile pyproject.toml --extra test --extra peers --extra slurm --universal \
		--python-version 3.11 --generate-hashes --index-url https://pypi.org/simple --quiet -o $(LOCK)

# The default checks (.ci/run): format and lint (ruff for the code, snakefmt for the rules,
# snakemake --lint), a dry run of the whole workflow, then the tests (which include the tiny
# end-to-end run of every rule, tests/test_workflow_tiny.py).
test: lint
	$(BIN)/python -m pytest

# The checks make test runs before the tests: format, lint, a dry run of the whole workflow
lint: install
	$(BIN)/ruff format --check --quiet .
	$(BIN)/ruff check --quiet .
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/python .ci/snakemake_lint.py $(BIN)/snakemake
	$(BIN)/snakemake -n all --quiet rules > /dev/null

format: install
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix --quiet .
	$(BIN)/snakefmt Snakefile workflow/rules

test-slow: install
	$(BIN)/python -m pytest -m slow

report: install
	$(BIN)/snakemake -j$(JOBS) --report results/report.html

# The README's cluster route without a cluster (.ci/run, after make test): the SLURM profile
# must parse and plan map2d. A dry run alone would not catch issue 17 (snakemake sets
# --cores 1 for dry runs), so --summary builds the same DAG as a real run, without submitting.
check-cluster: $(VENV)/.installed
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm -n map2d
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm --summary map2d > /dev/null
	@echo "check-cluster: the SLURM profile plans map2d"

# Opt-in, needs root: a one-node SLURM (Debian slurm-wlm, munge) runs a tiny map2d via sbatch.
check-slurm: $(VENV)/.installed
	bash workflow/slurm/check_slurm.sh --install

clean:
	rm -rf results/runs results/stats results/tables results/figures results/logs results/benchmarks
