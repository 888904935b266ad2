"""A run of part of a table (table_failures --only) is not the table: it never replaces the
whole table in the data folder, nor deletes the stored runs the whole table's sweep still needs;
and a bad --only is refused by the command line, before anything runs."""

import json

import pandas as pd
import pytest

from experiments import table_failures
from study import common, scenarios, systems
from study.common import SYSTEMS


def _fake_run(config, args):
    return pd.DataFrame({"x": [2.0]}), None, {}


def test_a_subset_leaves_the_table_and_the_store_alone(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    (data / "fake.csv").write_text("x\n1.0\n")
    store = tmp_path / "partial" / "fake-quick.jsonl"
    store.parent.mkdir()
    store.write_text('{"header": {}}\n')
    main = common.entry("fake", "A fake.", {}, {}, _fake_run, subset=lambda config, args: True)
    main(["--quick"], data_dir=data)
    assert (data / "fake.csv").read_text() == "x\n1.0\n"  # the whole table, untouched
    assert store.exists()  # the sweep's other runs are kept
    assert pd.read_csv(tmp_path / "only" / "fake.csv")["x"].tolist() == [2.0]
    assert (tmp_path / "only" / "fake.json").exists()


def test_the_whole_table_replaces_the_table_and_removes_the_store(tmp_path):
    data = tmp_path / "data"
    store = tmp_path / "partial" / "fake-quick.jsonl"
    store.parent.mkdir(parents=True)
    store.write_text('{"header": {}}\n')
    main = common.entry("fake", "A fake.", {}, {}, _fake_run, subset=lambda config, args: False)
    main(["--quick"], data_dir=data)
    assert pd.read_csv(data / "fake.csv")["x"].tolist() == [2.0]
    assert not store.exists() and not (tmp_path / "only").exists()


@pytest.mark.parametrize("only", ["nonexistent", ",", "slope_creep,nonexistent", ""])
def test_a_bad_only_is_a_usage_error(only, capsys):
    with pytest.raises(SystemExit) as stop:
        table_failures.main(["--quick", "--only", only])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "--only" in err and "Traceback" not in err


def test_only_every_scenario_is_the_whole_table():
    config = table_failures.QUICK
    parse = table_failures.scenario_names
    assert table_failures.is_subset(config, _args(parse("slope_creep")))
    assert not table_failures.is_subset(config, _args(parse(",".join(scenarios.SCENARIOS))))
    assert not table_failures.is_subset(config, _args(None))


def _args(only):
    class Args:
        pass

    args = Args()
    args.only = only
    return args


def test_only_one_scenario_end_to_end(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    (data / "table_failures.csv").write_text("scenario\nwhole table\n")
    table_failures.main(["--quick", "--only", "slope_creep"], data_dir=data)
    assert (data / "table_failures.csv").read_text() == "scenario\nwhole table\n"
    part = pd.read_csv(tmp_path / "only" / "table_failures.csv")
    assert set(part["scenario"]) == {"slope_creep"} and len(part) == len(SYSTEMS)
    meta = json.loads((tmp_path / "only" / "table_failures.json").read_text())
    assert list(meta["parameters"]["scenarios"]) == ["slope_creep"]
    # the configuration recorded is what ran (it listed all 13 scenarios)
    assert meta["parameters"]["config"]["scenarios"] == ["slope_creep"]
    assert meta["parameters"]["config"]["repeats"] == table_failures.QUICK["repeats"]
    # the store keeps the scenario's runs (truth + every system + sim's systems without the
    # presolve) for the whole table's run
    store = tmp_path / "partial" / "table_failures-quick.jsonl"
    runs = 1 + len(SYSTEMS) + len(systems.NO_PRESOLVE_SYSTEMS)
    assert len(store.read_text().splitlines()) == 1 + runs
