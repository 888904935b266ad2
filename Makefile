# freeze2d: every target runs inside .venv, which is built from the pins in pyproject.toml.
# Fresh clone, only python3 (>= 3.11) and make needed:  make test  |  make reproduce
#
#   make reproduce            every experiment, figure, table, recording and paper/paper.pdf
#   make reproduce QUICK=1    the same pipeline on small sizes, into results/quick/ (never mixes
#                             with the full results)
#   make <name>               rerun one experiment and redraw its figure (names: $(ALL))
#   make figures              redraw every figure/table from existing data; simulates only to
#                             remake data that is missing or older than the code it runs (an
#                             edit to sim/ or a shared study/ module reruns every experiment) or
#                             the installed package versions (a changed pin reruns them all)
#   make trace SCENE=slope_creep SYSTEMS=sim-off,sim-extended,pymunk-sleep
#   make trace CELL=table_extremes/dt/0.03333   one rerun recording of systems side by side;
#                                               open with `rerun <file>` (`make trace-list`)

PYTHON_SYS ?= python3
VENV       := .venv
PY         ?= $(VENV)/bin/python
STAMP      := $(VENV)/.installed
INSTALLED  := .make/installed.txt
QUICK      ?=
# QUICK=1 (yes, true, on) means the small sizes; QUICK=0 (no, false, off) or none the full ones.
# Any non-empty value used to mean quick, so QUICK=0 ran the quick pipeline; anything else is
# refused, not guessed.
QUICK_WORD := $(if $(QUICK),$(shell printf '%s' '$(QUICK)' | tr A-Z a-z))
ifneq ($(filter-out 1 yes true on 0 no false off,$(QUICK_WORD)),)
$(error QUICK=$(QUICK) is neither on nor off: use QUICK=1 (small sizes) or QUICK=0 (full sizes))
endif
IS_QUICK   := $(filter 1 yes true on,$(QUICK_WORD))
QUICKFLAG  := $(if $(IS_QUICK),--quick,)

# Where outputs go. Quick runs get their own tree, so a quick result is never taken for a full one.
# A tree named by FREEZE2D_RESULTS (the scripts' own setting; PAPER_OUT then <tree>/paper, as the
# analyses take it, unless FREEZE2D_PAPER_OUT names another) is the tree make builds and checks
# too: ignored, make looked at results/ and did nothing, or had the recipes write elsewhere.
# (Not the values a make exports to what it runs, FREEZE2D_FROM_MAKE set: a make run by a test
# under `make test` would take the outer make's tree for its own.)
given = $(or $(filter command line,$(origin $(1))),$(and $(filter environment,$(origin $(1))),$(if $(FREEZE2D_FROM_MAKE),,yes)))
ifneq ($(call given,FREEZE2D_RESULTS),)
RESULTS_DIR ?= $(FREEZE2D_RESULTS)
ifneq ($(call given,FREEZE2D_PAPER_OUT),)
PAPER_OUT   ?= $(FREEZE2D_PAPER_OUT)
else
PAPER_OUT   ?= $(FREEZE2D_RESULTS)/paper
endif
endif
ifneq ($(IS_QUICK),)
RESULTS_DIR ?= results/quick
PAPER_OUT   ?= results/quick/paper
else
RESULTS_DIR ?= results
PAPER_OUT   ?= paper
endif
export FREEZE2D_FROM_MAKE := 1
export FREEZE2D_RESULTS   := $(abspath $(RESULTS_DIR))
export FREEZE2D_PAPER_OUT := $(abspath $(PAPER_OUT))
DATA := $(RESULTS_DIR)/data
GEN  := $(PAPER_OUT)/generated
RECS := $(RESULTS_DIR)/recordings
ROWS := $(RECS)/table_failures

# The experiments: every experiments/<name>.py that has an analysis/<name>.py (one script per
# figure or table each), found here, so adding an experiment is adding its two scripts: no list to
# edit. (experiments/bench_setup.py has no analysis: a standalone benchmark, not in the pipeline.)
# In name order, so the benchmarks (bench_*) run first, on a machine not yet warmed by the sweeps.
# (bench_step also writes $(DATA)/bench_step_profile.csv, read by analysis/bench_step.py: MORE_DATA;
# bench_kernels reads the solver's compiled code: packed vector instructions, ns per contact.)
script_names = $(basename $(notdir $(wildcard $(1)/*.py)))
ALL := $(sort $(filter-out __init__,$(filter $(call script_names,analysis),$(call script_names,experiments))))
# One recording per figure scene, <builder>__<policy> (that policy alone), and one per row of the
# failure catalogue with every system of the table (table_failures/<scenario>.rrd; its index.txt
# lists them and their sizes)
RECORDINGS := seed_fig1__paper seed_fig2__paper seed_fig3__paper seed_fig3__extended \
              pyramid__extended drop__sleep drop__extended
RECORD_STEPS := $(if $(IS_QUICK),60,300)
# quick: the failure rows' first second only (the full rows run their own 3-7 s)
ROW_STEPS := $(if $(IS_QUICK),--steps 60,)

# make trace: a scene (builder, scenario or .toml file) under SYSTEMS, or a table cell (CELL)
SCENE ?= seed_fig3
SYSTEMS ?=
CELL ?=

.PHONY: all venv lint test test-fast reproduce figures paper glance recordings trace trace-list lock \
        clean distclean FORCE $(ALL)

# Serial even under `make -j`: the benchmarks time on a quiet machine, and the sweeps already fill
# every core through their own process pool (study/executor.py); a benchmark run beside a sweep
# would time the contention.
.NOTPARALLEL:

all: test

# The virtual environment is rebuilt whenever the pins change.
$(STAMP): pyproject.toml
	$(PYTHON_SYS) -c 'import sys; assert sys.version_info >= (3, 11), "freeze2d needs Python >= 3.11, found " + sys.version'
	$(PYTHON_SYS) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip==25.3
	$(VENV)/bin/python -m pip install --quiet -e '.[dev,pinned]'
	touch $@

venv: $(STAMP)

# Lint and format are checked first (ruff, pinned; pyproject.toml [tool.ruff]): fix with
# `.venv/bin/ruff check --fix . && .venv/bin/ruff format .`
lint: $(STAMP)
	$(PY) -m ruff check .
	$(PY) -m ruff format --check .

test: lint
	$(PY) -m pytest -q

# Every test but the slow tier (pipelines: make, scripts end to end; see tests/conftest.py), for
# development; CI runs `make test`.
test-fast: lint
	$(PY) -m pytest -q -m "not slow"

# The build graph: each output depends on every repository file its script runs, found from the
# imports by tools/makedeps.py (a list kept by hand went stale: an edit to bench_freeze.py did not
# rerun the figures that import it). The rules are remade whenever a source changes.
SOURCES := $(shell find sim study experiments analysis -name '*.py' -not -path '*/__pycache__/*')
DEPS    := .make/deps.mk
$(DEPS): tools/makedeps.py $(SOURCES) Makefile
	@mkdir -p $(dir $@)
	@$(PYTHON_SYS) tools/makedeps.py --out $@ $(ALL)
include $(DEPS)

reproduce: paper recordings glance

# Simulation: results/data/<name>.csv (+ .json) is rebuilt when its script or anything it imports
# (the solver included) changes, or when it is missing; the prerequisites beyond the script come
# from $(DEPS). A static pattern rule, so that the data files are explicit targets, never
# intermediate files: make neither deletes one after drawing its figure nor, if one is missing,
# calls the figure (outside results/) up to date. (They were marked `.SECONDARY:` for the first,
# which made every target secondary and gave the second: `rm -rf results` reran nothing.)
# Every file an experiment writes is needed (analysis refuses a .csv without its .json), but make
# tracks one target per experiment, the .csv, so that one run makes all of them: when any of the
# others is missing, the .csv is made again too (FORCE, through the second expansion, where $$*
# is the experiment's name). An experiment that writes more tables names them in
# MORE_DATA_<name>.
MORE_DATA_bench_step := bench_step_profile
outputs_of = $(1).json $(foreach t,$(MORE_DATA_$(1)),$(t).csv $(t).json)
missing_output = $(if $(filter-out $(wildcard $(addprefix $(DATA)/,$(call outputs_of,$(1)))),\
                   $(addprefix $(DATA)/,$(call outputs_of,$(1)))),FORCE)
DATA_FILES := $(foreach n,$(ALL),$(DATA)/$(n).csv)
.SECONDEXPANSION:
$(DATA_FILES): $(DATA)/%.csv: experiments/%.py $(INSTALLED) $$(call missing_output,$$*) | $(STAMP)
	$(PY) -m experiments.$* $(QUICKFLAG)
FORCE:

# The installed distributions and their versions (name==version, one a line), rewritten only when
# they change: a prerequisite of every simulation's output, so a changed pin reruns them once the
# venv has it. ($(STAMP) stays order-only: an edit to pyproject.toml that installs nothing new
# reruns nothing; before, a changed pin reran nothing at all.) Checked on every run, even under
# `make -n` (+), so that make compares the file's time after the check; skipped while there is no
# venv to ask (a dry run from a fresh clone), when everything is to be made anyway.
$(INSTALLED): FORCE | $(STAMP)
	+@if [ -e $(STAMP) ]; then $(PY) tools/installed.py $@; fi

# Analysis: figures, tables and the numbers the paper quotes; never simulates. make tracks the
# numbers, $(GEN)/<name>.json, which list the figures and tables written with them ("outputs"):
# when one of those is missing (deleted, moved aside), the analysis runs again (FORCE), as an
# experiment does when one of its data files is; a lost figure was never drawn again, and the
# paper then failed on it. LOST: those analyses, read once, when make first needs them.
LOST = $(eval LOST := $(shell $(PYTHON_SYS) tools/lost_outputs.py $(PAPER_OUT)))$(LOST)
$(GEN)/%.json: $(DATA)/%.csv analysis/%.py $$(if $$(filter $$*,$$(LOST)),FORCE) | $(STAMP)
	$(PY) -m analysis.$*

figures: $(foreach n,$(ALL),$(GEN)/$(n).json)

paper: $(PAPER_OUT)/paper.pdf
$(PAPER_OUT)/paper.pdf: paper/paper.typ $(PAPER_DEPS) $(foreach n,$(ALL),$(GEN)/$(n).json) | $(STAMP)
	$(PY) -m analysis.paper

# Results at a glance (and, for full runs, the README block between its markers). Its commit and
# machine are read from the data's metadata, as the paper's set-up is (analysis.paper imported:
# GLANCE_DEPS), not from generated/setup.json, which only the paper writes and this rule could not
# depend on without compiling the paper.
glance: $(GEN)/glance.md
$(GEN)/glance.md: $(GLANCE_DEPS) $(foreach n,$(ALL),$(GEN)/$(n).json) | $(STAMP)
	$(PY) -m analysis.glance $(if $(IS_QUICK),,--readme README.md)

recordings: $(foreach r,$(RECORDINGS),$(RECS)/$(r).rrd) $(ROWS)/index.txt
$(RECS)/%.rrd: $(TRACE_DEPS) $(INSTALLED) | $(STAMP)
	$(PY) -m analysis.trace $(word 1,$(subst __, ,$*)) --systems sim-$(word 2,$(subst __, ,$*)) \
	    --steps $(RECORD_STEPS) --out $@
# The rows' recordings are made in one run, tracked by their index.txt, which lists them: when one
# it lists is missing, they are made again (a lost row was never remade).
ROW_FILES = $(addprefix $(ROWS)/,$(filter %.rrd,\
              $(if $(wildcard $(ROWS)/index.txt),$(file <$(ROWS)/index.txt))))
lost_rows = $(filter-out $(wildcard $(ROW_FILES)),$(ROW_FILES))
$(ROWS)/index.txt: $(TRACE_DEPS) $(INSTALLED) $$(if $$(lost_rows),FORCE) | $(STAMP)
	$(PY) -m analysis.trace --table table_failures $(ROW_STEPS) --out-dir $(dir $@)

# `make <name>`: rerun one experiment unconditionally, then redraw what it feeds.
$(ALL): $(STAMP)
	$(PY) -m experiments.$@ $(QUICKFLAG)
	$(PY) -m analysis.$@

# A rerun recording of systems side by side on one scene or table cell, into results/recordings/:
#   make trace SCENE=slope_creep SYSTEMS=sim-off,sim-extended,pymunk-sleep
#   make trace CELL=table_failures/slope_creep      (every system of the row, as the table ran it)
# SCENE: a builder, a failure-catalogue scenario or a scene file (.toml); `make trace-list` names
# them all. Open the file it writes with `.venv/bin/rerun <file>`.
trace: $(STAMP)
	$(PY) -m analysis.trace $(if $(CELL),$(CELL),$(SCENE)) $(if $(SYSTEMS),--systems '$(SYSTEMS)',)

trace-list: $(STAMP)
	$(PY) -m analysis.trace --list

# Print the currently installed versions, to refresh the `pinned` extra by hand.
lock: $(STAMP)
	$(PY) -m pip freeze --exclude-editable

# `make print-ALL` etc.: the value of a variable (the end-to-end test reads the lists from here)
print-%:
	@echo $($*)

clean:
	rm -rf results paper/figures paper/generated paper/paper.pdf

distclean: clean
	rm -rf $(VENV)
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
