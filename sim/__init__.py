"""freeze2d's 2D rigid-body solver for convex polygons, with switchable freezing of resting bodies.

import sim
world = sim.World(sim.scenes.pyramid(20), dt=1/60, iterations=10, freeze="off")
world.step(600)
world.positions, world.angles, world.states, world.events
"""

import hashlib as _hashlib
import os as _os
import pathlib as _pathlib
import shutil as _shutil

import numba as _numba


def _use_source_keyed_cache():
    """Point Numba's on-disk cache at a folder named by a hash of every sim source file.

    Numba invalidates a cached kernel only when the kernel's own file changes, not when a kernel it
    calls (in another module) does: after an edit to geometry.py, the cached contact kernels would
    silently keep the old collision code. Keying the cache folder by all sources makes any edit
    recompile everything once."""
    here = _pathlib.Path(__file__).parent
    digest = _hashlib.sha256()
    for f in sorted(here.rglob("*.py")):
        digest.update(f.relative_to(here).as_posix().encode())
        digest.update(f.read_bytes())
    key = digest.hexdigest()[:16]
    root = _pathlib.Path(_os.environ.get("NUMBA_CACHE_DIR") or here / "__pycache__" / "numba")
    for old in root.glob("*"):  # caches of earlier sources are dead weight
        if old.is_dir() and old.name != key and len(old.name) == 16:
            _shutil.rmtree(old, ignore_errors=True)
    _numba.config.CACHE_DIR = str(root / key)


_use_source_keyed_cache()

from .body import Body  # noqa: E402  (after the cache is set up, before any kernel is compiled)
from .freeze import POLICY_NAMES  # noqa: E402
from .geometry import PolygonError  # noqa: E402
from .scene import Scene  # noqa: E402
from .state import State  # noqa: E402
from .world import SimulationError, World  # noqa: E402
from . import scenes  # noqa: E402

__all__ = [
    "Body",
    "Scene",
    "World",
    "State",
    "scenes",
    "PolygonError",
    "SimulationError",
    "POLICY_NAMES",
]
