"""Writing files so that a failure never leaves a damaged one: ``write_text_atomically``.

Used by ``Scene.to_file`` and by the study's results writers: a run interrupted mid-write (Ctrl-C,
a full disk, an unwritable value found half-way) must leave the old file whole, not truncated."""

import os
import tempfile
from pathlib import Path


def write_text_atomically(path, text):
    """Write ``text`` to ``path``: to a temporary file beside it, flushed to disk, then renamed
    over it (a rename within one folder is atomic). On any failure the old file is untouched
    and the temporary one removed."""
    path = Path(path)
    if not path.parent.is_dir():  # else mkstemp's error names the hidden temporary file
        raise FileNotFoundError(f"cannot write {path}: the folder {path.parent} does not exist")
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)  # mkstemp makes it owner-only
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
