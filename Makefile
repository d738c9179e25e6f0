# Every target sets up what it needs: a fresh clone needs only Python 3.11 and make.
PYTHON ?= python3.11
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
# Blender as a Python module: 5.0 in .venv, 4.5 LTS in a second environment
BPY ?= 5.0.1
BPY45 ?= 4.5.15
VENV45 := .venv-bpy45
STAMP45 := $(VENV45)/.installed

.PHONY: help venv test lint demo benchmark extension fuzz clean

help:
	@echo "make demo       set up, then simplify the bundled samples (SVG, and a .blend via the operator) into out/"
	@echo "make test       set up, then run the whole test suite (add-on on Blender 5.0 and 4.5)"
	@echo "make benchmark  the report: reports/benchmark/index.html over ../shared/data,"
	@echo "                then Stable Across Frames on moving drawings (bench_stable.py)"
	@echo "make extension  build dist/sketchsimp-<version>-<platform>.zip for Blender"
	@echo "make fuzz       10,000 random and adversarial sketches through core.simplify, counted by kind"
	@echo "make lint       ruff"

$(STAMP): pyproject.toml
	@command -v $(PYTHON) >/dev/null || { echo "Python 3.11 is needed (set PYTHON=...)"; exit 1; }
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev,cluster]" "bpy==$(BPY)"
	touch $(STAMP)

$(STAMP45): pyproject.toml
	@command -v $(PYTHON) >/dev/null || { echo "Python 3.11 is needed (set PYTHON=...)"; exit 1; }
	test -x $(VENV45)/bin/python || $(PYTHON) -m venv $(VENV45)
	$(VENV45)/bin/python -m pip install --quiet --upgrade pip
	$(VENV45)/bin/python -m pip install --quiet -e ".[dev]" "bpy==$(BPY45)"
	touch $(STAMP45)

venv: $(STAMP)

test: $(STAMP) $(STAMP45)
	$(PY) -m pytest
	$(VENV45)/bin/python -m pytest tests/test_addon.py tests/test_batch.py

lint: $(STAMP)
	$(PY) -m ruff check core sketchsimp_addon tests scripts

demo: $(STAMP)
	$(PY) scripts/demo.py
	$(PY) scripts/demo_blender.py house

fuzz: $(STAMP)
	$(PY) scripts/fuzz.py --examples 10000

extension: $(STAMP)
	$(PY) scripts/build_extension.py

benchmark: $(STAMP)
	$(PY) scripts/bench_complex.py
	$(PY) scripts/report.py
	$(PY) scripts/bench_stable.py

clean:
	rm -rf $(VENV) $(VENV45) dist out reports .pytest_cache .hypothesis
