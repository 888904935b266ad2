"""Every script's --help: exit status 0, and the description is its docstring's whole first
paragraph (the first line alone stopped mid-sentence: "...packed vector instructions,")."""

import importlib
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NAMES = subprocess.run(
    ["make", "-s", "print-ALL"], cwd=ROOT, capture_output=True, text=True, check=True
).stdout.split()


def _words(text):
    return " ".join(text.split())


def _help(module, capsys):
    with pytest.raises(SystemExit) as stop:
        module.main(["--help"])
    assert stop.value.code in (0, None)
    return _words(capsys.readouterr().out)


@pytest.mark.parametrize("name", NAMES + ["bench_setup"])
def test_an_experiments_help_is_its_first_paragraph(name, capsys):
    module = importlib.import_module(f"experiments.{name}")
    first = _words(module.__doc__.strip().split("\n\n")[0])
    assert first in _help(module, capsys)


@pytest.mark.parametrize("name", NAMES)
def test_an_analysis_has_help(name, capsys):
    module = importlib.import_module(f"analysis.{name}")
    out = _help(module, capsys)
    assert f"python -m analysis.{name}" in out
    assert _words(module.__doc__.strip().split("\n\n")[0]) in out


def test_an_analysis_refuses_an_option_as_usage(capsys):
    module = importlib.import_module("analysis.fig_states")
    with pytest.raises(SystemExit) as stop:
        module.main(["--bogus"])
    assert stop.value.code == 2 and "--bogus" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["glance", "paper", "trace"])
def test_the_pipelines_own_tools_have_their_first_paragraph_as_help(name, capsys):
    module = importlib.import_module(f"analysis.{name}")
    assert _words(module.__doc__.strip().split("\n\n")[0]) in _help(module, capsys)
