"""The analyses to run again because a figure or table they wrote has gone missing since.

    python3 tools/lost_outputs.py PAPER_OUT      names on standard output, one per line

Each ``analysis/<name>.py`` records in ``PAPER_OUT/generated/<name>.json`` ("outputs") the
figures and tables it wrote, relative to PAPER_OUT. make tracked only that .json: a figure moved
aside or deleted was never drawn again, and the paper then failed on it. The Makefile runs this
when it first needs it and forces those analyses, as it forces an experiment one of whose data
files is missing. Standard library only: it runs before the virtualenv may exist.
"""

import json
import sys
from pathlib import Path


def lost(paper_out):
    """Sorted names of the analyses one of whose recorded outputs under ``paper_out`` is missing
    (an unreadable .json is left to the analysis' own rule: it is remade when its data is)."""
    paper_out = Path(paper_out)
    names = set()
    for numbers in sorted((paper_out / "generated").glob("*.json")):
        try:
            outputs = json.loads(numbers.read_text()).get("outputs", [])
            if any(not (paper_out / output).exists() for output in outputs):
                names.add(numbers.stem)
        except (OSError, ValueError, AttributeError, TypeError):
            continue
    return sorted(names)


if __name__ == "__main__":
    print("\n".join(lost(sys.argv[1])))
