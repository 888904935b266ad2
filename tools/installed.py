"""The distributions installed for the interpreter that runs this, one ``name==version`` a line.

    .venv/bin/python tools/installed.py FILE      writes FILE, only when what it holds differs

The Makefile makes every data file depend on FILE (.make/installed.txt): a changed pin reruns
the experiments once the virtualenv has it, and only then (the venv's own stamp is an
order-only prerequisite, so an edit to pyproject.toml that installs nothing new reruns nothing).
The file keeps its time when nothing changed, so make reruns nothing either.
"""

import importlib.metadata
import sys
from pathlib import Path


def installed():
    """Sorted ``name==version`` of every distribution this interpreter can import from."""
    found = set()
    for dist in importlib.metadata.distributions():
        name = dist.metadata["Name"]
        if name:  # a damaged .dist-info has none
            found.add(f"{name.lower()}=={dist.version}")
    return sorted(found)


def refresh(path):
    """Write ``installed()`` to ``path`` if it differs from what the file holds; True if so."""
    path = Path(path)
    text = "".join(line + "\n" for line in installed())
    if path.exists() and path.read_text() == text:
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)
    return True


if __name__ == "__main__":
    refresh(sys.argv[1])
