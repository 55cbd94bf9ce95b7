# Two commands do everything on a fresh machine with Python 3.11:
#   make        install into .venv and run the full workflow (snakemake -j2)
#   make test   install into .venv and run the default (fast) tests
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
JOBS ?= 2

.PHONY: all install test test-slow report lint check-cluster check-slurm clean

all: install
	$(BIN)/snakemake -j$(JOBS)

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test,peers]'
	touch $@

install: $(VENV)/.installed

test: install
	$(BIN)/python -m pytest

test-slow: install
	$(BIN)/python -m pytest -m slow

report: install
	$(BIN)/snakemake -j$(JOBS) --report results/report.html

lint: install
	$(BIN)/snakemake --lint

$(VENV)/.installed-slurm: $(VENV)/.installed pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[slurm]'
	touch $@

# The README's cluster route without a cluster (.ci/run, after make test): the SLURM profile
# must parse and plan map2d. A dry run alone would not catch issue 17 (snakemake sets
# --cores 1 for dry runs), so --summary builds the same DAG as a real run, without submitting.
check-cluster: $(VENV)/.installed-slurm
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm -n map2d
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm --summary map2d > /dev/null
	@echo "check-cluster: the SLURM profile plans map2d"

# Opt-in, needs root: a one-node SLURM (Debian slurm-wlm, munge) runs a tiny map2d via sbatch.
check-slurm: $(VENV)/.installed-slurm
	bash workflow/slurm/check_slurm.sh --install

clean:
	rm -rf results/runs results/stats results/tables results/figures results/logs results/benchmarks
