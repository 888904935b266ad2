"""Writing files so that a failure never leaves a damaged one: ``write_text_atomically``.

Used by ``Scene.to_file`` and by the study's results writers: a run interrupted mid-write (Ctrl-C,
a full disk, an unwritable value found half-way) must leave the old file whole, not truncated."""

import hashlib
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


#: the key under which ``seal`` records a scene file's checksum
SEAL_KEY = "sha256"
SEAL_NOTE = (
    "the sha256 line above is of the rest of this file; delete it to load the file after an edit"
)


def seal(data, dumps):
    """``data`` (a dict a TOML file is written from) with its checksum first: the SHA-256 of
    ``dumps(data)``, the text the rest of the file is. A scene file cut short at a line kept
    loading, as another scene: 20 of 111 cuts of one file lost a static wall, a body, or a
    body's friction and name to their defaults, without an error."""
    digest = hashlib.sha256(dumps(data).encode()).hexdigest()
    return {SEAL_KEY: digest, "sha256_note": SEAL_NOTE, **data}


def check_seal(data, dumps, path):
    """``data`` as read from ``path`` without its seal; ValueError if it has one that its
    contents do not match. A file without a seal (written by hand, or its seal deleted after an
    edit) is taken as it is."""
    data = dict(data)
    data.pop("sha256_note", None)  # the seal's note, left when only the sha256 line is deleted
    if SEAL_KEY not in data:
        return data
    recorded = data.pop(SEAL_KEY)
    if (
        not isinstance(recorded, str)
        or hashlib.sha256(dumps(data).encode()).hexdigest() != recorded
    ):
        raise ValueError(
            f"{path}: its contents are not what was written (the sha256 it records differs): "
            f"cut short or edited. If you edited it, delete its sha256 line to load it as it is"
        )
    return data
