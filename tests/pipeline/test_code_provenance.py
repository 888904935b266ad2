"""Results name the code that made them: the git state is read when a run starts, and a commit
or an edit made before it ends is said in the metadata (``code_changed_during_run``, ``git.dirty``
true, ``git_at_end``), never hidden behind the newer commit's name. The runs are fakes in a
throwaway git repository: what is checked is the provenance, not a measurement."""

import json
import subprocess

import pandas as pd
import pytest

from experiments import peer_agreement
from study import common, paths


def _git(repo, *args):
    return subprocess.run(
        ["git", "-C", str(repo), *args], capture_output=True, text=True, check=True
    ).stdout.strip()


@pytest.fixture
def repo(tmp_path, monkeypatch):
    """A git repository with one commit, standing in for the project's."""
    root = tmp_path / "repo"
    root.mkdir()
    _git(root, "init", "-q")
    _git(root, "config", "user.email", "t@example.com")
    _git(root, "config", "user.name", "t")
    (root / "script.py").write_text("x = 1\n")
    _git(root, "add", "script.py")
    _git(root, "commit", "-q", "-m", "first")
    monkeypatch.setattr(paths, "ROOT", root)
    return root


def _commit_a_change(root):
    (root / "script.py").write_text("x = 2\n")
    _git(root, "commit", "-q", "-am", "second")


def _experiment(during):
    def run(config, args):
        during()
        return pd.DataFrame({"x": [1.0]}), None, {}

    return common.entry("fake", "A fake.", {}, {}, run)


def _meta(folder, name="fake"):
    return json.loads((folder / f"{name}.json").read_text())


def test_a_commit_during_the_run_is_said_not_hidden(repo, tmp_path):
    first = _git(repo, "rev-parse", "HEAD")
    _experiment(lambda: _commit_a_change(repo))([], data_dir=tmp_path / "data")
    meta = _meta(tmp_path / "data")
    assert meta["git"]["commit"] == first  # the code that started the run
    assert meta["git"]["dirty"] is True  # no one clean commit made these results
    assert meta["code_changed_during_run"] is True
    assert meta["git_at_end"]["commit"] == _git(repo, "rev-parse", "HEAD") != first


def test_an_edit_during_the_run_is_said(repo, tmp_path):
    def edit():
        (repo / "script.py").write_text("x = 3\n")

    _experiment(edit)([], data_dir=tmp_path / "data")
    meta = _meta(tmp_path / "data")
    assert meta["code_changed_during_run"] is True and meta["git"]["dirty"] is True


def test_an_unchanged_tree_is_a_clean_commit(repo, tmp_path):
    _experiment(lambda: None)([], data_dir=tmp_path / "data")
    meta = _meta(tmp_path / "data")
    assert meta["git"] == {"commit": _git(repo, "rev-parse", "HEAD"), "dirty": False}
    assert meta["code_changed_during_run"] is False and "git_at_end" not in meta


def test_an_experiment_with_its_own_command_line_reads_git_at_the_start(
    repo, tmp_path, monkeypatch
):
    first = _git(repo, "rev-parse", "HEAD")
    table = pd.DataFrame({"case": ["fall"], "reference_kind": ["exact"]})

    def run(sizes, repeats, steps):
        _commit_a_change(repo)
        return table

    monkeypatch.setattr(peer_agreement, "run", run)
    peer_agreement.main(["--quick"], data_dir=tmp_path / "data")
    meta = _meta(tmp_path / "data", "peer_agreement")
    assert meta["git"]["commit"] == first and meta["code_changed_during_run"] is True


def test_every_distribution_the_code_imports_has_its_version_recorded():
    # llvmlite (sim/clock.py, bench_kernels) was imported directly but missing from the versions
    # a results file records. Read from the imports: a new dependency cannot be forgotten.
    import ast
    import importlib.metadata
    import re
    import sys

    from study import metadata

    def normal(name):
        return re.sub(r"[-_.]+", "-", name).lower()

    own = ("sim", "study", "experiments", "analysis")
    top = set()
    for folder in own:
        for path in (paths.ROOT / folder).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Import):
                    top |= {alias.name.split(".")[0] for alias in node.names}
                elif isinstance(node, ast.ImportFrom) and not node.level:
                    top.add(node.module.split(".")[0])
    third_party = top - set(sys.stdlib_module_names) - set(own)
    distributions = importlib.metadata.packages_distributions()
    imported = {normal(d) for module in third_party for d in distributions[module]}
    assert "llvmlite" in imported and "numba" in imported
    missing = imported - {normal(name) for name in metadata.PACKAGES}
    assert not missing, f"imported but not recorded in study.metadata.PACKAGES: {sorted(missing)}"


@pytest.mark.parametrize("changed", [True, False, "unknown"])
def test_results_made_while_the_code_changed_are_dated_so_make_reruns_them(tmp_path, changed):
    """Dated when written, results of a run during which a module was edited were newer than the
    edit, and make took them as up to date (until 2026-12-07): they are dated at the epoch, and
    the next make reruns the experiment. Results of unchanged code keep their date."""
    import pandas as pd

    from study.metadata import write_results

    paths_ = write_results(
        "x", pd.DataFrame({"a": [1]}), {"code_changed_during_run": changed}, folder=tmp_path
    )
    for path in paths_:
        assert path.exists()
        assert (path.stat().st_mtime == 0) == (changed is True)
