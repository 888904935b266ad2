"""--scheduler is offered only by the experiments that sweep (their untimed runs go through the
executor), and recorded only there; a scheduler that cannot be used is one line, not a
traceback."""

import json

import pandas as pd
import pytest

from experiments import (
    bench_fast_paths,
    bench_kernels,
    fig_edge_as_floor,
    fig_overhang,
    fig_scaling,
    fig_speedup,
    fig_states,
    fig_time_to_rest,
    fig_tradeoff,
    table_extremes,
    table_failures,
)
from study import common, executor

NO_SWEEP = [
    fig_states,
    fig_speedup,
    fig_scaling,
    fig_overhang,
    fig_edge_as_floor,
    bench_kernels,
    bench_fast_paths,
]
SWEEPS = [fig_tradeoff, table_failures, table_extremes, fig_time_to_rest]


@pytest.mark.parametrize("module", NO_SWEEP, ids=lambda m: m.NAME)
def test_a_script_without_a_sweep_refuses_scheduler(module, capsys):
    with pytest.raises(SystemExit) as stop:
        module.main(["--quick", "--scheduler", "not-an-address"])
    assert stop.value.code == 2
    assert "--scheduler" in capsys.readouterr().err


@pytest.mark.parametrize("module", SWEEPS, ids=lambda m: m.NAME)
def test_a_sweep_offers_scheduler(module, capsys):
    with pytest.raises(SystemExit) as stop:
        module.main(["--help"])
    assert stop.value.code == 0
    assert "--scheduler" in capsys.readouterr().out


def _table(config, args):
    return pd.DataFrame({"x": [1.0]}), None, {}


def test_only_a_sweep_records_its_executor(tmp_path, monkeypatch):
    # set through monkeypatch (empty: no scheduler), so that the address main() writes into
    # os.environ is taken back after the test: left there, every later sweep used it
    monkeypatch.setenv(executor.SCHEDULER_ENV, "")
    common.entry("plain", "No sweep.", {}, {}, _table)([], data_dir=tmp_path)
    assert "executor" not in json.loads((tmp_path / "plain.json").read_text())["parameters"]
    common.entry("swept", "A sweep.", {}, {}, _table, sweep=True)([], data_dir=tmp_path)
    meta = json.loads((tmp_path / "swept.json").read_text())
    assert meta["parameters"]["executor"] == "local process pool"


def test_an_unusable_scheduler_is_one_line(tmp_path, monkeypatch):
    import distributed

    def refused(address, *args, **kwargs):
        raise OSError(f"Timed out trying to connect to {address} after 30 s")

    monkeypatch.setattr(distributed, "Client", refused)
    # set through monkeypatch (empty: no scheduler), so that the address main() writes into
    # os.environ is taken back after the test: left there, every later sweep used it
    monkeypatch.setenv(executor.SCHEDULER_ENV, "")

    def run(config, args):
        executor.run_tasks(abs, [1, 2])
        return _table(config, args)

    main = common.entry("swept", "A sweep.", {}, {}, run, sweep=True)
    with pytest.raises(SystemExit) as stop:
        main(["--scheduler", "tcp://127.0.0.1:1"], data_dir=tmp_path)
    message = str(stop.value.code)
    assert "tcp://127.0.0.1:1" in message and "\n" not in message
    assert not (tmp_path / "swept.csv").exists()
