# Two commands do everything on a fresh machine with Python 3.11:
#   make        install into .venv and build the paper: every figure and number of it (snakemake -j2)
#   make test   install into .venv, run lint and format checks, build the docs, run the default
#               tests on both cores (pytest -n 2; make test-slow runs the slow ones)
# Beyond the paper, on request: make beyond (orbits, Lyapunov exponents, basins, two-parameter
# curves, the noise study, identification and predictions), make bench (the benchmarks: every job
# that times, each with the machine to itself) and make everything (the three).
# Both install the exact versions of requirements.lock (hash-checked) with uv, itself pinned with
# its hashes in requirements-uv.lock; `make lock` refreshes both locks.
PYTHON ?= python3
LOCK := requirements.lock
VENV := .venv
BIN := $(VENV)/bin
JOBS ?= 2
# pytest's workers (pytest-xdist) in make test and make test-slow: two, as the workflow's jobs. Not
# -n auto: it would start one worker per core of a large machine, each paying the imports and the
# module-scoped fixtures of its files, and the tiny workflow build runs two jobs of its own; the
# budget of make test is measured on 2 cores. pyproject's addopts send each file to one worker
# (--dist loadfile); tests/conftest.py compiles the numba core into the shared cache before the
# workers start.
PYTEST_WORKERS ?= 2
PYTEST_PARALLEL := -n $(PYTEST_WORKERS)
# uv lives in a venv of its own: `uv pip sync` removes from .venv whatever the lock does not list
UV_VERSION := 0.13.8
UV_LOCK := requirements-uv.lock
UV_VENV := .tools/uv
UV := $(UV_VENV)/bin/uv
# extra arguments of the workflow run, e.g. make SNAKEMAKE_ARGS='fig05 --configfile my.yaml'
SNAKEMAKE_ARGS ?=
# The study that make report and make clean act on: its results are results/$(STUDY)/ (config
# key study; a full run takes it from the config: make SNAKEMAKE_ARGS='--config study=myrig')
STUDY ?= paper
# STUDY names a folder that make clean removes: an empty or unsafe name (results/, ..) must stop
# it, so the name is checked as the config checks the key (letters, digits, _ and -)
CHECK_STUDY = case "$(STUDY)" in ""|*[!A-Za-z0-9_-]*) echo "STUDY='$(STUDY)': letters, digits, _ and - only" >&2; exit 1;; esac

.PHONY: all beyond bench everything laws install lock test test-slow report lint docs config-docs format check-cluster check-slurm check-snakemake clean

# A build killed part-way resumes with a plain `make`: a lock left by a dead Snakemake is removed
# (never one a live Snakemake holds, workflow/unlock_stale.py) and incomplete outputs are redone.
# Two recipe lines, two shells: a shell running both would itself look like a live Snakemake in
# this directory to unlock_stale.py, which would then keep the dead build's lock.
define snakemake_run
	$(BIN)/python workflow/unlock_stale.py
	$(BIN)/snakemake -j$(JOBS) --rerun-incomplete $(1)
endef
# The model the paper's study identifies (make beyond): its predictions with error bars are a study
# of their own, results/identified/
IDENTIFIED = results/$(STUDY)/models/identified.yaml

# The paper (rule all): results/paper/, its table results/paper/tables/paper_vs_replication.md,
# and the report of its figures, results/paper/report.html (for the default build; make report
# writes one for other targets or configs)
all: install
	$(call snakemake_run,$(SNAKEMAKE_ARGS))
	$(if $(SNAKEMAKE_ARGS),,$(BIN)/snakemake --quiet all --report results/paper/report.html)

# Beyond the paper (rule beyond), then the predictions with error bars of the model it identifies
beyond: install
	$(call snakemake_run,beyond $(SNAKEMAKE_ARGS))
	$(call snakemake_run,predictions --config study=identified model_file=$(IDENTIFIED))

# The benchmarks (rule benchmarks): each timing job claims every core (config timing.exclusive)
bench: install
	$(call snakemake_run,benchmarks $(SNAKEMAKE_ARGS))

everything: all beyond bench

# The laws study (opt-in, results/laws/): Figs 2 and 3b of model BC beside Hertz and Flores, Flores's
# e matched to model BC's dissipation (config/laws.yaml; workflow/rules/laws.smk states its budget)
laws: install
	$(call snakemake_run,laws_study --configfile config/laws.yaml $(SNAKEMAKE_ARGS))

# uv, pinned and hash-checked, bootstrapped by the venv's own pip (no uv on the machine needed)
$(UV): $(UV_LOCK)
	rm -rf $(UV_VENV)
	$(PYTHON) -m venv $(UV_VENV)
	$(UV_VENV)/bin/python -m pip install --quiet --require-hashes --no-deps -r $(UV_LOCK)
	touch $@

# the interpreter of .venv is the one $(PYTHON) names; uv never downloads one
$(BIN)/python: | $(UV)
	$(UV) venv --quiet --clear --no-python-downloads --python "$$($(PYTHON) -c 'import sys; print(sys.executable)')" $(VENV)

# The tested environment: every package pinned with its hashes (extras test, peers, slurm, docs, explore),
# exactly (sync removes what the lock does not list), then the package itself, built by the
# locked setuptools (no unpinned build environment). Bytecode is compiled at install, as pip
# does and uv does not by default: without it every job of the workflow compiles numba, SciPy
# and matplotlib from source on import when .pyc files cannot be written (PYTHONDONTWRITEBYTECODE),
# about 1 s per job.
$(VENV)/.installed: $(BIN)/python $(LOCK) pyproject.toml | $(UV)
	$(UV) pip sync --quiet --python $(BIN)/python --require-hashes --compile-bytecode $(LOCK)
	$(UV) pip install --quiet --python $(BIN)/python --no-deps --no-build-isolation -e .
	touch $@

install: $(VENV)/.installed

# Refresh the locks after changing pyproject's dependencies or UV_VERSION (uv resolves for every
# platform from its configured index, PyPI unless the user's uv configuration says otherwise).
lock: $(UV)
	$(UV) pip compile pyproject.toml --extra test --extra peers --extra slurm --extra docs --extra explore --universal \
		--python-version 3.11 --generate-hashes --quiet -o $(LOCK)
	echo "uv==$(UV_VERSION)" | $(UV) pip compile - --universal --python-version 3.11 --generate-hashes \
		--quiet -o $(UV_LOCK)

# The default checks (.ci/run, budget 8 min from a fresh clone on 2 cores): format and lint (ruff
# for the code, snakefmt for the rules, snakemake --lint), a dry run of the whole workflow, the docs
# build, then the default tests (pyproject's addopts: -m 'not slow') on both cores. Among them is
# the one end-to-end run of the workflow, every rule on config/tiny.yaml
# (tests/test_workflow_tiny.py); the other full-pipeline builds are slow tests.
test: lint docs
	$(BIN)/python -m pytest $(PYTEST_PARALLEL)

# The checks make test runs before the tests: format, lint, the import contract (pyproject's
# [tool.importlinter]: the library never imports the study or the benchmarks, no layer imports
# a higher one), a dry run of the whole workflow
lint: install
	$(BIN)/lint-imports --no-cache --no-logo
	$(BIN)/ruff format --check --quiet .
	$(BIN)/ruff check --quiet .
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/python .ci/snakemake_lint.py $(BIN)/snakemake
	$(BIN)/snakemake -n all --quiet rules > /dev/null

# The documentation site into site/, strict: a broken link or reference, or public API without a
# docstring (docs/hooks.py), fails the build. make test builds it too.
docs: install
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

# config/README.md, every key of the workflow config, rendered from its schema (a test checks it is current)
config-docs: install
	$(BIN)/python -m impactosc_study.config_docs

format: install
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix --quiet .
	$(BIN)/snakefmt Snakefile workflow/rules

# The rest: full-length scenes, long numerical checks, the workflow builds other than the tiny one
# (resume after a kill, a second study, rig records, the longest tutorials)
test-slow: install
	$(BIN)/python -m pytest $(PYTEST_PARALLEL) -m slow

# The report of one study (make report STUDY=myrig: results/myrig/report.html) from the files its
# build wrote; a study with a config file of its own names it in SNAKEMAKE_ARGS='--configfile
# config/config.yaml my.yaml' (not --config, which the study's --config here would override).
report: install
	@$(CHECK_STUDY)
	$(BIN)/snakemake -j$(JOBS) $(SNAKEMAKE_ARGS) --report results/$(STUDY)/report.html --config study=$(STUDY)

# The cluster route (docs/workflow.md) without a cluster (.ci/run, after make test): the SLURM profile
# must parse and plan map2d. A dry run alone would not catch a broken profile (snakemake sets
# --cores 1 for dry runs), so --summary builds the same DAG as a real run, without submitting.
check-cluster: $(VENV)/.installed
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm -n map2d
	$(BIN)/snakemake --workflow-profile workflow/profiles/slurm --summary map2d > /dev/null
	@echo "check-cluster: the SLURM profile plans map2d"

# Opt-in, needs root: a one-node SLURM (Debian slurm-wlm, munge) runs a tiny map2d via sbatch.
check-slurm: $(VENV)/.installed
	bash workflow/slurm/check_slurm.sh --install

# Opt-in, needs the package index (PyPI): the workflow on the oldest and the newest Snakemake of
# pyproject's range, each in a throw-away venv with the package (.ci/check_snakemake.py): dry runs
# of all, beyond and benchmarks, and a build of everything on config/tiny.yaml. Run it before
# changing the range or bumping Snakemake in the lock (docs/development.md). Measured: 22 min on
# 2 cores shared with other work (9.11.6: 12.6 min, 9.27.1: 9.6 min; load average 2 to 15).
check-snakemake: $(UV)
	$(PYTHON) .ci/check_snakemake.py $(UV)

# One study's results (make clean STUDY=myrig; default paper) and the docs site; other studies'
# results stay, and so does the numba cache (outside results/, keyed on the core's sources).
clean:
	@$(CHECK_STUDY)
	rm -rf results/$(STUDY) site
