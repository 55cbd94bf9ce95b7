# Two commands do everything on a fresh machine with Python 3.11:
#   make        install into .venv and run the full workflow (snakemake -j2)
#   make test   install into .venv and run the default (fast) tests
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
JOBS ?= 2

.PHONY: all install test test-slow report lint clean

all: install
	$(BIN)/snakemake -j$(JOBS)

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test]'
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

clean:
	rm -rf results/runs results/stats results/tables results/figures results/logs
