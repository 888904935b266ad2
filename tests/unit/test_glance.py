"""The README's results bullets say what the numbers say, in the study's protocol."""

from analysis.glance import extremes_line


def _extremes(per_axis, fair):
    return {
        "cells": 4,
        "counts": {"sim-off": {"failed": 0}, "pymunk": {"failed": 1}},
        "per_axis": per_axis,
        "breaks_first": fair,
        "no_presolve": {
            "suffix": " (no presolve)",
            "axes": ["stack_height"],
            "cells": 2,
            "counts": {"sim-off (no presolve)": {"failed": 1, "degraded": 0}},
        },
    }


def test_the_extremes_bullet_quotes_the_fair_headline():
    """Where sim's presolve decides who breaks first on a placed axis, the README must quote the
    fair rows (sim without it), not the rows sim wins with it."""
    with_presolve = {
        "stack_height": {"breaks_first": ["pymunk"], "breaks_first_at": "50"},
        "dt": {"breaks_first": ["pymunk"], "breaks_first_at": "1/15 s"},
    }
    fair = {
        "stack_height": {"breaks_first": ["sim-off (no presolve)"], "breaks_first_at": "10"},
        "dt": {"breaks_first": ["pymunk"], "breaks_first_at": "1/15 s"},
    }
    line = extremes_line(_extremes(with_presolve, fair))
    assert "stack height: sim-off (no presolve) (at 10)" in line
    assert "stack height: pymunk" not in line
    assert "dt: pymunk (at 1/15 s)" in line
    assert "failed per system: sim-off 0, pymunk 1" in line
    assert "On the 1 axes that start placed at rest" in line
    assert "sim-off 1 failed / 0 degraded" in line
