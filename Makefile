# freeze2d: every target runs inside .venv, which is built from the pins in pyproject.toml.
# Fresh clone, only python3 (>= 3.11) and make needed:  make test  |  make reproduce

PYTHON_SYS ?= python3
VENV       := .venv
PY         := $(VENV)/bin/python
STAMP      := $(VENV)/.installed
QUICK      ?=
QUICKFLAG  := $(if $(QUICK),--quick,)
DATA       := results/data

.PHONY: all venv test test-fast reproduce bench_step lock clean distclean

all: test

# The virtual environment is rebuilt whenever the pins change.
$(STAMP): pyproject.toml
	$(PYTHON_SYS) -c 'import sys; assert sys.version_info >= (3, 11), "freeze2d needs Python >= 3.11, found " + sys.version'
	$(PYTHON_SYS) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip==25.3
	$(PY) -m pip install --quiet -e '.[dev,pinned]'
	touch $@

venv: $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

# Everything the study produces. Later issues add figures, recordings and the paper here.
reproduce: $(DATA)/bench_step.csv

$(DATA)/bench_step.csv: $(STAMP) $(wildcard sim/*.py) experiments/bench_step.py
	$(PY) -m experiments.bench_step $(QUICKFLAG)

bench_step: $(STAMP)
	$(PY) -m experiments.bench_step $(QUICKFLAG)

# Print the currently installed versions, to refresh the `pinned` extra by hand.
lock: $(STAMP)
	$(PY) -m pip freeze --exclude-editable

clean:
	rm -rf results

distclean: clean
	rm -rf $(VENV)
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
