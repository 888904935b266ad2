"""A count given on the command line (--repeats, --steps) is an integer >= 1: 0 is refused like a
negative (argparse: exit status 2, one line naming the option), never taken for the default, and
left out it is the default. Nothing may run before the refusal: each experiment's measurement is
replaced by one that fails the test if called."""

import pytest

from experiments import bench_freeze, bench_setup, bench_step, peer_agreement, table_failures
from study import cli


def _never(*args, **kwargs):
    raise AssertionError("the experiment ran despite a bad count")


CASES = [
    (bench_freeze, "run", ["--repeats"]),
    (bench_step, "run", ["--repeats", "--steps"]),
    (peer_agreement, "run", ["--repeats", "--steps"]),
    (table_failures, "compile_kernels", ["--repeats"]),
    (bench_setup, "arrays_run", ["--repeats"]),
]


@pytest.mark.parametrize("value", ["0", "-2", "two"])
@pytest.mark.parametrize(
    "module, option",
    [(m, o) for m, _, options in CASES for o in options],
    ids=lambda x: getattr(x, "__name__", x),
)
def test_a_bad_count_is_a_usage_error(module, option, value, monkeypatch, capsys):
    stage = next(name for m, name, _ in CASES if m is module)
    monkeypatch.setattr(module, stage, _never)
    with pytest.raises(SystemExit) as stop:
        module.main(["--quick", option, value])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert option in err and "Traceback" not in err


def test_a_count_left_out_is_the_default():
    assert cli.or_default(None, 7) == 7
    assert cli.or_default(3, 7) == 3
    assert cli.positive_int("1") == 1
