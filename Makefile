# Every target sets up what it needs: a fresh clone needs only Python 3.11 and make.
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: help venv test lint demo benchmark clean

help:
	@echo "make demo       set up, then simplify a bundled sample sketch into out/"
	@echo "make test       set up, then run the whole test suite"
	@echo "make benchmark  timings and quality scores over ../shared/data"
	@echo "make lint       ruff"

$(STAMP): pyproject.toml
	@command -v $(PYTHON) >/dev/null || { echo "Python 3.11 is needed (set PYTHON=...)"; exit 1; }
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev]"
	touch $(STAMP)

venv: $(STAMP)

test: $(STAMP)
	$(PY) -m pytest

lint: $(STAMP)
	$(PY) -m ruff check core tests scripts

demo: $(STAMP)
	$(PY) scripts/demo.py

benchmark: $(STAMP)
	$(PY) scripts/bench_complex.py
	$(PY) scripts/bench_simplify.py

clean:
	rm -rf $(VENV) dist out reports .pytest_cache .hypothesis
