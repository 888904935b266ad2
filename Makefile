# freeze2d: every target runs inside .venv, which is built from the pins in pyproject.toml.
# Fresh clone, only python3 (>= 3.11) and make needed:  make test  |  make reproduce

PYTHON_SYS ?= python3
VENV       := .venv
PY         := $(VENV)/bin/python
STAMP      := $(VENV)/.installed
QUICK      ?=
QUICKFLAG  := $(if $(QUICK),--quick,)
DATA       := results/data

EXPERIMENTS := bench_step bench_freeze peer_agreement

SCENE ?= seed_fig3
FREEZE ?= paper

.PHONY: all venv test reproduce trace lock clean distclean $(EXPERIMENTS)

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

# Everything the study produces. Each results file is rebuilt when its script or the solver
# changes; `make <name>` reruns one experiment unconditionally.
reproduce: $(addprefix $(DATA)/,$(addsuffix .csv,$(EXPERIMENTS)))

SIM_SOURCES := $(wildcard sim/*.py sim/freeze/*.py)
PEER_SOURCES := $(wildcard experiments/peers/*.py) experiments/metadata.py experiments/paths.py

$(DATA)/%.csv: experiments/%.py $(SIM_SOURCES) $(PEER_SOURCES) | $(STAMP)
	$(PY) -m experiments.$* $(QUICKFLAG)

$(EXPERIMENTS): $(STAMP)
	$(PY) -m experiments.$@ $(QUICKFLAG)

# A rerun recording of one run: make trace SCENE=pyramid FREEZE=extended; open with `rerun <file>`
trace: $(STAMP)
	$(PY) -m analysis.trace $(SCENE) $(FREEZE)

# Print the currently installed versions, to refresh the `pinned` extra by hand.
lock: $(STAMP)
	$(PY) -m pip freeze --exclude-editable

clean:
	rm -rf results

distclean: clean
	rm -rf $(VENV)
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
