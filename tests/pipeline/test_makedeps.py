"""The Makefile's build graph comes from the imports (tools/makedeps.py): an edit to any module
reruns exactly the experiments and analyses that run it, and nothing else."""

import json

import pytest
import os
import re
import subprocess
import sys
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import makedeps  # noqa: E402


def _make_list(variable):
    out = subprocess.run(
        ["make", "-s", f"print-{variable}"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    return out.split()


def test_dependencies_follow_imports_through_other_modules():
    speedup = makedeps.dependencies("experiments.fig_speedup")
    assert "study/protocols.py" in speedup  # a library module
    assert "study/cost_fit.py" in speedup  # ... and what it imports
    assert "study/common.py" in speedup and "sim/world.py" in speedup
    assert "sim/freeze/extended.py" in speedup  # through sim/freeze/__init__
    assert "experiments/fig_states.py" not in speedup
    assert "experiments/bench_freeze.py" not in speedup  # a script: never a library
    table = makedeps.dependencies("analysis.table_extremes")
    assert "study/extremes/axes.py" in table  # analysis importing a library
    assert "study/extremes/__init__.py" in table  # (a package's __init__ runs)
    assert "experiments/table_extremes.py" not in table
    # a relative import (study/metadata.py: from . import paths)
    assert "study/paths.py" in makedeps.dependencies("study.metadata")


@pytest.fixture(scope="module")
def built_tree(tmp_path_factory):
    """A results tree in which every data file and figure is up to date (newer than any source)."""
    results = tmp_path_factory.mktemp("results")
    paper = tmp_path_factory.mktemp("paper")
    names = _make_list("ALL")
    later = time.time() + 3600
    # every file an experiment writes: <name>.csv + .json, and bench_step's profile
    data = [f"{n}{s}" for n in names + ["bench_step_profile"] for s in (".csv", ".json")]
    for i, (folder, files) in enumerate(
        ((results / "data", data), (paper / "generated", [f"{n}.json" for n in names]))
    ):
        folder.mkdir(parents=True, exist_ok=True)
        for file in files:
            target = folder / file
            target.write_text("")
            os.utime(target, (later + 60 * i, later + 60 * i))  # figures after their data
    return results, paper, names


def _dry_run(built_tree, edited):
    """What `make -n figures` prints if ``edited`` were changed."""
    results, paper, _ = built_tree
    return subprocess.run(
        ["make", "-n", "-W", edited, f"RESULTS_DIR={results}", f"PAPER_OUT={paper}", "figures"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout


def _rebuilt(built_tree, edited):
    """(experiments rerun, analyses rerun) by `make -n figures` if ``edited`` were changed."""
    out = _dry_run(built_tree, edited)
    return (
        set(re.findall(r"-m experiments\.(\w+)", out)),
        set(re.findall(r"-m analysis\.(\w+)", out)),
    )


def test_an_up_to_date_tree_rebuilds_nothing(built_tree):
    assert _rebuilt(built_tree, "README.md") == (set(), set())


def test_an_edit_to_a_library_module_reruns_what_imports_it(built_tree):
    users = {"bench_freeze", "fig_speedup", "fig_scaling", "fig_time_to_rest"}
    assert _rebuilt(built_tree, "study/protocols.py") == (users, users)
    assert _rebuilt(built_tree, "study/cost_fit.py") == (users, users)  # via protocols
    # a script is imported by nothing: its edit reruns itself only
    assert _rebuilt(built_tree, "experiments/bench_freeze.py") == (
        {"bench_freeze"},
        {"bench_freeze"},
    )


def test_a_missing_data_file_is_rerun(built_tree):
    # A data file deleted (or lost) while its figure exists is made again, and the figure redrawn:
    # the figures live outside results/, so `rm -rf results && make reproduce` must rerun every
    # experiment. Marked secondary (as every target was, by a bare `.SECONDARY:`) a missing one
    # was not: make called the figure up to date and kept it, drawn from data no longer there.
    # Nor may make delete the data file once the figure is drawn (as an intermediate file).
    results, _, _ = built_tree
    data = results / "data" / "bench_freeze.csv"
    stamp = data.stat().st_mtime
    data.unlink()
    try:
        assert _rebuilt(built_tree, "README.md") == ({"bench_freeze"}, {"bench_freeze"})
        assert "rm " not in _dry_run(built_tree, "README.md")
    finally:
        data.write_text("")
        os.utime(data, (stamp, stamp))


@pytest.mark.parametrize(
    "lost, rerun",
    [
        ("fig_states.json", "fig_states"),  # analysis refuses a .csv without its .json
        ("bench_step_profile.csv", "bench_step"),  # bench_step writes it too
        ("bench_step_profile.json", "bench_step"),
    ],
)
def test_any_missing_data_file_reruns_the_experiment_that_writes_it(built_tree, lost, rerun):
    # make tracked only <name>.csv: a lost .json, or a lost second table, was never made again
    # ("Nothing to be done for 'figures'") and the analysis then failed
    results, _, _ = built_tree
    data = results / "data" / lost
    stamp = data.stat().st_mtime
    data.unlink()
    try:
        assert _rebuilt(built_tree, "README.md") == ({rerun}, {rerun})
    finally:
        data.write_text("")
        os.utime(data, (stamp, stamp))


def test_a_missing_figure_or_table_is_drawn_again(built_tree):
    # make tracked only generated/<name>.json: a figure moved aside was never drawn again ("Nothing
    # to be done") and the paper then failed on it. The .json lists what its analysis wrote.
    _, paper, _ = built_tree
    numbers = paper / "generated" / "fig_speedup.json"
    stamp = numbers.stat().st_mtime
    outputs = ["figures/fig_speedup.svg", "generated/fig_speedup.csv"]
    numbers.write_text(json.dumps({"numbers": {}, "outputs": outputs}))
    os.utime(numbers, (stamp, stamp))
    try:
        (paper / "figures").mkdir(exist_ok=True)
        (paper / "generated" / "fig_speedup.csv").write_text("")
        assert _rebuilt(built_tree, "README.md") == (set(), {"fig_speedup"})  # the figure
        (paper / "figures" / "fig_speedup.svg").write_text("")
        assert _rebuilt(built_tree, "README.md") == (set(), set())  # all there
        (paper / "generated" / "fig_speedup.csv").unlink()
        assert _rebuilt(built_tree, "README.md") == (set(), {"fig_speedup"})  # the table
    finally:
        numbers.write_text("")
        os.utime(numbers, (stamp, stamp))


def test_a_missing_row_recording_is_made_again(built_tree, tmp_path):
    # the rows' recordings were tracked by their index.txt alone: a lost one was never remade
    results, paper, _ = built_tree
    later = time.time() + 3600
    rows = results / "recordings" / "table_failures"
    rows.mkdir(parents=True, exist_ok=True)
    files = [results / "recordings" / f"{r}.rrd" for r in _make_list("RECORDINGS")]
    files += [rows / "tipping.rrd", rows / "overhang.rrd", rows / "index.txt"]
    for file in files:
        file.write_text("")
        os.utime(file, (later, later))
    (rows / "index.txt").write_text(
        "# one recording per row\ntipping.rrd\t0.46 MB\noverhang.rrd\t1 MB\n"
    )
    os.utime(rows / "index.txt", (later, later))

    def recorded():
        out = subprocess.run(
            ["make", "-n", f"RESULTS_DIR={results}", f"PAPER_OUT={paper}", "recordings"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        return re.findall(r"-m analysis\.trace (\S+)", out)

    try:
        assert recorded() == []
        (rows / "tipping.rrd").rename(tmp_path / "tipping.rrd")  # moved aside
        assert recorded() == ["--table"]
    finally:
        for file in files:
            file.unlink(missing_ok=True)


def test_a_change_of_installed_versions_reruns_the_experiments(tmp_path):
    # $(STAMP) was order-only for the data files: a changed pin rebuilt the venv and reran
    # nothing. The data depend on the installed versions (a file rewritten only when they change),
    # not on pyproject.toml: an edit that installs nothing new reruns nothing.
    results, paper, installed = tmp_path / "results", tmp_path / "paper", tmp_path / "installed"
    names = _make_list("ALL")
    now = time.time()
    data = [f"{n}{s}" for n in names + ["bench_step_profile"] for s in (".csv", ".json")]
    for folder, files, when in (
        (results / "data", data, now - 2),
        (paper / "generated", [f"{n}.json" for n in names], now - 1),
    ):
        folder.mkdir(parents=True)
        for file in files:
            (folder / file).write_text("")
            os.utime(folder / file, (when, when))

    def rebuilt(held):
        installed.write_text(held)
        os.utime(installed, (now - 3, now - 3))  # older than the data
        out = subprocess.run(
            ["make", "-n", f"RESULTS_DIR={results}", f"PAPER_OUT={paper}"]
            + [f"INSTALLED={installed}", "figures"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        return set(re.findall(r"-m experiments\.(\w+)", out))

    subprocess.run([sys.executable, "tools/installed.py", str(installed)], cwd=ROOT, check=True)
    assert rebuilt(installed.read_text()) == set()  # the same versions: nothing
    assert rebuilt("numpy==0.0\n") == set(names)  # another version: every experiment


def test_the_makefile_header_says_what_make_figures_does(built_tree):
    # it said "never simulates", yet after an edit to a shared library module make figures reruns
    # every experiment (its data is older than the code it runs)
    header = (ROOT / "Makefile").read_text().split("\n\n")[0]
    figures = header[header.index("make figures") :].split("#   make ")[0]
    assert _rebuilt(built_tree, "study/metadata.py")[0] == set(built_tree[2])
    assert "never simulates" not in figures and "older than the code" in figures


def test_an_edit_to_the_solver_reruns_every_experiment(built_tree):
    names = set(built_tree[2])
    assert _rebuilt(built_tree, "sim/contacts.py") == (names, names)


def test_an_edit_to_an_analysis_module_redraws_only_what_imports_it(built_tree):
    assert _rebuilt(built_tree, "analysis/filmstrip.py") == (
        set(),
        {"fig_states", "fig_edge_as_floor", "fig_overhang"},
    )
    # an experiment script: its data, then its figure
    experiments, analyses = _rebuilt(built_tree, "experiments/table_extremes.py")
    assert experiments == {"table_extremes"} and analyses == {"table_extremes"}
    # a library module that both the experiment and its analysis import
    for edited in ("study/extremes/axes.py", "study/extremes/judge.py"):
        assert _rebuilt(built_tree, edited) == ({"table_extremes"}, {"table_extremes"}), edited


def test_the_solver_imports_nothing_from_the_study():
    # ARCHITECTURE §1: sim/ stands alone (the study imports it, never the reverse)
    for path in sorted((ROOT / "sim").rglob("*.py")):
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        outside = [f for f in makedeps.dependencies(module) if not f.startswith("sim/")]
        assert not outside, f"{module} runs {outside}"


def _module(path):
    """The dotted module name of a repository file."""
    return ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")


def test_no_experiment_script_runs_another_nor_does_analysis():
    """ARCHITECTURE §5: the layers import downwards only. An experiment script imports sim and the
    study library, never another script (so a script can change without changing another's
    results); analysis imports sim and study, never a script; study imports neither experiments
    nor analysis; sim imports none of them (tests/adapters/test_peers.py). Read from the imports,
    transitively (every module a module runs)."""
    scripts = {f"experiments/{name}.py" for name in _make_list("ALL")}
    assert "experiments/bench_freeze.py" in scripts
    packages = [d.name for d in ROOT.glob("experiments/*/") if d.name != "__pycache__"]
    assert not packages, f"experiments/ holds scripts only: {packages} belong in study/"

    def runs(path, layer):
        own = str(path.relative_to(ROOT))
        return {
            f
            for f in makedeps.dependencies(_module(path))
            if f.startswith(layer) and f != own and not f.endswith("__init__.py")
        }

    for path in sorted(ROOT.glob("experiments/*.py")):
        assert not runs(path, "experiments/"), (
            f"{path.name} imports the experiment script(s) {sorted(runs(path, 'experiments/'))}:"
            f" move what it uses into study/"
        )
    for path in sorted(ROOT.glob("analysis/**/*.py")):
        assert not runs(path, "experiments/"), (
            f"analysis/{path.name} imports {sorted(runs(path, 'experiments/'))}: analysis reads "
            f"results and imports sim and study only"
        )
    for path in sorted(ROOT.glob("study/**/*.py")):
        for layer in ("experiments/", "analysis/"):
            assert not runs(path, layer), (
                f"{path.relative_to(ROOT)} imports {sorted(runs(path, layer))}: the study "
                f"library never imports the scripts above it"
            )


def test_no_module_outside_tests_is_over_600_lines():
    """ARCHITECTURE §5: small modules with one job. A module that grows past this is split by job
    (as sim/soft_step/, sim/freeze/extended*.py, study/scenarios/ were)."""
    long = {
        str(path.relative_to(ROOT)): n
        for folder in ("sim", "study", "experiments", "analysis", "tools")
        for path in sorted((ROOT / folder).rglob("*.py"))
        if (n := len(path.read_text().splitlines())) > 600
    }
    assert not long, f"modules over 600 lines: {long}"


def test_every_experiment_with_an_analysis_is_in_the_pipeline():
    """ARCHITECTURE §5: adding an experiment is adding experiments/<name>.py and analysis/<name>.py;
    the Makefile finds the pairs, so there is no list to forget."""
    pairs = {
        p.stem
        for p in ROOT.glob("experiments/*.py")
        if not p.stem.startswith("_") and (ROOT / "analysis" / p.name).exists()
    }
    assert set(_make_list("ALL")) == pairs
    assert {"bench_step", "fig_speedup", "table_failures", "table_extremes"} <= pairs
    assert "bench_setup" not in pairs  # a standalone benchmark: no analysis, not in reproduce


def test_make_runs_serially_even_when_asked_for_jobs():
    # `make -j reproduce` ran benchmarks beside the pool's sweeps, timing the contention: the
    # Makefile declares itself serial (.NOTPARALLEL), which make's own database must show
    database = subprocess.run(
        ["make", "-pnq", "-j2", "venv"], cwd=ROOT, capture_output=True, text=True
    ).stdout
    assert re.search(r"^\.NOTPARALLEL:", database, re.M)


@pytest.mark.parametrize(
    "quick, tree, flag",
    [
        ("0", "results", ""),
        ("no", "results", ""),
        ("False", "results", ""),
        ("", "results", ""),
        ("1", "results/quick", "--quick"),
        ("yes", "results/quick", "--quick"),
    ],
)
def test_quick_0_no_false_mean_the_full_sizes(quick, tree, flag):
    # any non-empty QUICK meant quick: `make reproduce QUICK=0` ran the small sizes
    # a tree named in the environment is make's tree (FREEZE2D_RESULTS): not here
    env = {k: v for k, v in os.environ.items() if not k.startswith("FREEZE2D_")}

    def value(variable):
        return subprocess.run(
            ["make", "-s", f"print-{variable}", f"QUICK={quick}"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
            env=env,
        ).stdout.strip()

    assert (value("RESULTS_DIR"), value("QUICKFLAG")) == (tree, flag)


def test_a_tree_named_by_freeze2d_results_is_makes_tree_unless_make_exported_it():
    """make honours FREEZE2D_RESULTS given on its command line or in the environment (it looked
    at results/ and did nothing, until 2026-12-07), but not the one a make exports to what it
    runs (a make run by a test under `make test`)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("FREEZE2D_")}

    def value(variable, *args, **extra):
        return subprocess.run(
            ["make", "-s", f"print-{variable}", *args],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
            env={**env, **extra},
        ).stdout.strip()

    assert value("RESULTS_DIR", FREEZE2D_RESULTS="/tmp/tree") == "/tmp/tree"
    assert value("PAPER_OUT", FREEZE2D_RESULTS="/tmp/tree") == "/tmp/tree/paper"
    assert value("RESULTS_DIR", "FREEZE2D_RESULTS=/tmp/tree") == "/tmp/tree"
    exported = {"FREEZE2D_RESULTS": "/tmp/tree", "FREEZE2D_FROM_MAKE": "1"}
    assert value("RESULTS_DIR", **exported) == "results"


def test_a_quick_value_that_is_neither_on_nor_off_is_refused():
    out = subprocess.run(
        ["make", "-s", "print-RESULTS_DIR", "QUICK=maybe"], cwd=ROOT, capture_output=True, text=True
    )
    assert out.returncode != 0 and "QUICK=maybe is neither on nor off" in out.stderr


def test_a_failed_write_of_the_rules_stops_with_the_file_named_and_leaves_nothing(tmp_path):
    """The rules are written whole or not at all, and a failure is an error make sees (through
    the shell's redirection, a full disk cut deps.mk short with exit status 0)."""
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("")
    with pytest.raises(SystemExit, match="cannot write .*deps.mk"):
        makedeps.write(blocker / "deps.mk", "rules\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["not_a_folder"]
    good = tmp_path / "deps.mk"
    makedeps.write(good, "rules\n")
    assert good.read_text() == "rules\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deps.mk", "not_a_folder"]
