"""Analysis reads only whole results files: the .json records its CSV's row count and SHA-256
when both are written, and a CSV cut short, edited or missing, or a damaged .json, is refused with
one line naming the file and the experiment to rerun (exit status 1, no traceback), never drawn
from in part."""

import json

import pandas as pd
import pytest

from analysis import bench_step as a_bench_step
from analysis import glance, paper, style
from study import metadata, paths

TABLE = pd.DataFrame({"scenario": [f"s{i}" for i in range(200)], "value": range(200)})


def _draw(table, meta):
    return {"rows": len(table)}


FAKE = style.entry("fake", _draw)


@pytest.fixture
def data(tmp_path, monkeypatch):
    monkeypatch.setattr(paths, "DATA", tmp_path / "data")
    monkeypatch.setattr(paths, "FIGURES", tmp_path / "figures")
    monkeypatch.setattr(paths, "GENERATED", tmp_path / "generated")
    metadata.write_results("fake", TABLE, {"script": "fake", "parameters": {}})
    return tmp_path / "data"


def _refused(main, argv=()):
    with pytest.raises(SystemExit) as stop:
        main(list(argv))
    message = str(stop.value.code)
    assert "\n" not in message  # one line (SystemExit with a message exits with status 1)
    return message


def test_a_whole_file_is_read(data):
    assert FAKE([]) == {"rows": 200}
    meta = json.loads((data / "fake.json").read_text())
    assert meta["csv"]["rows"] == 200 and len(meta["csv"]["sha256"]) == 64


def test_the_numbers_name_the_data_file_they_were_read_from(data):
    # every generated .json said "results/data/<name>.csv": wrong for a quick tree's data, and
    # for the set-up, which has no data file
    FAKE([])
    numbers = json.loads((paths.GENERATED / "fake.json").read_text())
    assert numbers["source"] == str(data / "fake.csv")  # outside the repository: absolute
    quick = paths.ROOT / "results" / "quick" / "data" / "fake.csv"
    style.write_numbers("fake", {}, {}, source=quick)
    numbers = json.loads((paths.GENERATED / "fake.json").read_text())
    assert numbers["source"] == "results/quick/data/fake.csv"
    style.write_numbers("setup", {}, {})
    assert "source" not in json.loads((paths.GENERATED / "setup.json").read_text())


def test_a_csv_cut_mid_line_is_refused(data):
    csv = data / "fake.csv"
    csv.write_bytes(csv.read_bytes()[:1000])
    message = _refused(FAKE)
    assert str(csv) in message and "rows" in message and "python -m experiments.fake" in message


def test_a_csv_cut_at_a_line_end_is_refused(data):
    csv = data / "fake.csv"
    csv.write_text("".join(csv.read_text().splitlines(keepends=True)[:61]))
    assert "60 rows where its .json records 200" in _refused(FAKE)


def test_an_edited_csv_is_refused(data):
    csv = data / "fake.csv"
    csv.write_text(csv.read_text().replace("s17,", "s71,"))
    assert "SHA-256" in _refused(FAKE)


def test_a_damaged_json_is_refused_by_name(data):
    (data / "fake.json").write_text('{"script": "fake", "csv": {')
    message = _refused(FAKE)
    assert str(data / "fake.json") in message and "damaged" in message


def test_missing_data_is_refused_by_name(data):
    (data / "fake.csv").unlink()
    assert f"{data / 'fake.csv'} is missing" in _refused(FAKE)
    (data / "fake.json").unlink()
    assert f"{data / 'fake.json'} is missing" in _refused(FAKE)


def test_metadata_without_a_checksum_is_refused(data):
    meta = json.loads((data / "fake.json").read_text())
    del meta["csv"]
    (data / "fake.json").write_text(json.dumps(meta))
    assert "older code" in _refused(FAKE)


@pytest.mark.parametrize("rows, sha", [("200", None), (200.0, None), (True, None), (None, 7)])
def test_a_checksum_record_of_the_wrong_types_is_refused_not_misreported(data, rows, sha):
    """rows "3" gave "x.csv has 3 rows where its .json records 3" (a reviewer, 2026-12-07)."""
    meta = json.loads((data / "fake.json").read_text())
    if rows is not None:
        meta["csv"]["rows"] = rows
    if sha is not None:
        meta["csv"]["sha256"] = sha
    (data / "fake.json").write_text(json.dumps(meta))
    assert "records no row count and checksum of fake.csv" in _refused(FAKE)


def test_a_folder_in_place_of_the_csv_is_one_line(data):
    (data / "fake.csv").unlink()
    (data / "fake.csv").mkdir()
    assert f"{data / 'fake.csv'} cannot be read" in _refused(FAKE)


def test_the_paper_refuses_metadata_without_the_set_up_it_reads(data):
    """Valid JSON without "cpu" was a KeyError in analysis.paper (a traceback)."""
    meta = metadata.collect(None, {}, script="fig_speedup")
    del meta["cpu"]
    metadata.write_results("fig_speedup", TABLE, meta)
    message = _refused(paper.main)
    assert str(data / "fig_speedup.json") in message and "(no cpu)" in message


def test_the_profile_names_its_own_file_and_experiment(data):
    """bench_step writes bench_step_profile.csv as well; the analysis names the missing one and
    the experiment that writes it (there is no make bench_step_profile)."""
    with pytest.raises(metadata.ResultsError) as refused:
        style.load(a_bench_step.PROFILE, script=a_bench_step.NAME)
    message = str(refused.value)
    assert "bench_step_profile.json is missing" in message
    assert "`make bench_step`" in message and "`python -m experiments.bench_step`" in message


def test_the_paper_refuses_damaged_metadata_by_name(data):
    (data / "fake.json").write_text("not json")
    message = _refused(paper.main)
    assert str(data / "fake.json") in message


def test_the_glance_refuses_missing_numbers_in_one_line_naming_its_target(data):
    # it raised FileNotFoundError (a traceback) for generated/setup.json, advising `make figures`,
    # which never writes that file; it now reads the set-up from the data's metadata itself
    meta = metadata.collect(None, {}, script="fig_speedup")
    metadata.write_results("fig_speedup", TABLE, meta)
    message = _refused(glance.main)
    assert f"{paths.GENERATED / 'fig_speedup.json'} is missing" in message
    assert "`make glance`" in message and "`python -m analysis.fig_speedup`" in message
    for name in ("fake", "fig_speedup"):  # and without any experiment's metadata
        (data / f"{name}.json").unlink()
    assert "no experiment metadata" in _refused(glance.main)


def test_the_paper_names_a_missing_input_and_what_writes_it(data, tmp_path, monkeypatch):
    # typst's "file not found" was an uncaught TypstError traceback
    out = tmp_path / "paper_out"
    monkeypatch.setattr(paths, "PAPER_OUT", out)
    monkeypatch.setattr(paths, "GENERATED", out / "generated")
    monkeypatch.setattr(paths, "FIGURES", out / "figures")
    monkeypatch.setattr(paths, "PDF", out / "paper.pdf")
    metadata.write_results("fig_speedup", TABLE, metadata.collect(None, {}, script="fig_speedup"))
    message = _refused(paper.main)  # no analysis has run: the first numbers the paper reads
    assert " is missing: `make paper` draws it again, or `python -m analysis." in message
    assert str(out / "generated") in message
    # a figure: named by the analysis whose numbers list it among their outputs
    numbers = {"numbers": {}, "outputs": ["figures/fig_extremes.svg"]}
    (out / "generated" / "table_extremes.json").write_text(json.dumps(numbers))
    message = paper.missing_input(out / "figures" / "fig_extremes.svg", out)
    assert message.endswith("`python -m analysis.table_extremes`"), message
    assert "no analysis records writing it" in paper.missing_input(out / "figures" / "x.svg", out)


def test_the_rerun_hint_for_quick_data_names_the_quick_run(tmp_path):
    # the hint named `make <name>` (full size) for a file of results/quick/data
    quick = tmp_path / "quick" / "data"
    quick.mkdir(parents=True)
    with pytest.raises(metadata.ResultsError) as err:
        metadata.read_results(quick, "fig_states")
    assert "`make fig_states QUICK=1` or `python -m experiments.fig_states --quick`" in str(
        err.value
    )
    full = tmp_path / "data"
    full.mkdir()
    with pytest.raises(metadata.ResultsError) as err:
        metadata.read_results(full, "fig_states")
    assert "`make fig_states` or `python -m experiments.fig_states`" in str(err.value)


def test_a_run_given_no_seed_records_the_seeds_of_its_scenes():
    """The top-level seed was null in 11 of 15 results files, the random piles' among them: a
    script that names no seed now records its scenes' seeds (None only when none is random)."""
    import sim

    piles = [sim.scenes.drop(3, seed=7), sim.scenes.drop(3, seed=2), sim.scenes.stack(2)]
    assert metadata.collect(piles, {}, script="test")["seed"] == [2, 7]
    assert metadata.collect(sim.scenes.stack(2), {}, script="test")["seed"] is None


def test_a_seed_a_run_gives_does_not_hide_its_scenes_seeds():
    """bench_freeze gave its drift seed (0) and hid its piles' seeds 0-2; fig_time_to_rest's
    100-pile sample, run but not listed as scenes, was missing from its seeds: the record holds
    both."""
    import sim

    piles = [sim.scenes.drop(3, seed=7), sim.scenes.drop(3, seed=2)]
    assert metadata.collect(piles, {}, script="test", seed=5)["seed"] == [2, 5, 7]
    assert metadata.collect(piles, {}, script="test", seed=[9, 2])["seed"] == [2, 7, 9]
    assert metadata.collect(sim.scenes.stack(2), {}, script="test", seed=0)["seed"] == [0]
