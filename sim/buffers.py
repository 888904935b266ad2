"""The arrays the compiled step loop works in (``sim.data``): built once from the packed scene,
and grown, contents carried over, when a step outgrows them.

Split from ``world.py`` by job: the World decides *when* (it builds once, and grows when a step
returns GROW, then calls the step again); this module knows *how big* each buffer is and how its
contents move to a larger one. Nothing here is called inside the step loop (no allocation
there, ARCHITECTURE §2), and a run is bit-identical whatever sizes the buffers started at.
"""

import numpy as np

from . import data as D
from . import soft_step
from .broadphase import grid_buffers
from .continuous import toi_scratch
from .tolerances import body_margin, body_slop, body_speculative


def aligned(shape, dtype=np.float64):
    """A zeroed array whose data starts on a 64-byte boundary (a solver row is one cache line)."""
    n = int(np.prod(shape))
    itemsize = np.dtype(dtype).itemsize
    raw = np.zeros(n * itemsize + 64, np.uint8)
    offset = (-raw.ctypes.data) % 64
    return raw[offset : offset + n * itemsize].view(dtype).reshape(shape)


def new_bodies(p, slop, speculative_distance):
    """``data.Bodies`` of the packed scene ``p`` (``sim.packing``), with each body's tolerances
    scaled from the World's caps ``slop`` and ``speculative_distance`` (m, ``sim.tolerances``)."""
    return D.Bodies(
        position=p.position,
        angle=p.angle,
        velocity=p.velocity,
        angular_velocity=p.angular_velocity,
        inv_mass=p.inv_mass,
        inv_inertia=p.inv_inertia,
        friction=p.friction,
        restitution=p.restitution,
        vert_start=p.vert_start,
        local_verts=p.local_verts,
        local_normals=p.local_normals,
        extent=p.extent,
        size=p.size,
        slop=body_slop(p.size, slop),
        speculative=body_speculative(p.size, speculative_distance),
        margin=body_margin(p.size, speculative_distance),
        bullet=p.bullet,
    )


def new_geometry(p):
    """``data.Geometry`` for the packed scene ``p``: room for the world vertices and boxes, and
    every fat box empty, so that each body's first box refits it."""
    n = p.n_dynamic
    m = len(p.angle)
    v_total = len(p.local_verts)
    fat = np.empty((m, 4))
    fat[:, :2] = np.inf  # an empty box: every body's first box refits it
    fat[:, 2:] = -np.inf
    return D.Geometry(
        rotation=np.empty((m, 2)),
        world_verts=np.empty((v_total, 2)),
        world_normals=np.empty((v_total, 2)),
        aabb=np.empty((m, 4)),
        fat=fat,
        moved=np.zeros(n, np.int64),
        moved_flag=np.zeros(n, bool),
        partner=np.zeros(m, bool),
        toi_scratch=toi_scratch(int(np.diff(p.vert_start).max())),
    )


def new_contacts(capacity, n):
    """An empty ``data.Contacts`` store of ``capacity`` slots for ``n`` dynamic bodies."""
    return D.Contacts(
        contact_int=np.zeros((capacity, D.CONTACT_INT), np.int64),
        contact_float=np.zeros((capacity, D.CONTACT_FLOAT)),
        point_float=np.zeros((capacity, 2, D.POINT_FLOAT)),
        point_id=np.full((capacity, 2), -1, np.int64),
        head=np.full(n, -1, np.int64),
        degree=np.zeros(n, np.int64),
        awake=np.zeros(capacity, np.int64),
        active=np.zeros(capacity, np.int64),
        scratch_points=np.zeros((2, 2)),
        scratch_separations=np.zeros(2),
        scratch_ids=np.zeros(2, np.int64),
        scratch_normal=np.zeros(2),
    )


def new_solver(n, n_contacts, max_degree, old=None):
    """A ``data.Solver`` for ``n`` dynamic bodies, ``n_contacts`` active contacts and bodies
    with up to ``max_degree`` contacts; the profile counters carry over from ``old`` (the solver
    it replaces, if any), so a regrown World keeps its timings."""
    batches = soft_step.capacity(n_contacts, max_degree)
    words = soft_step.mask_words(max_degree)
    return D.Solver(
        state=aligned((n + 1, D.STATE_COLUMNS)),
        colour_mask=np.zeros((n + 1, words), np.uint64),
        colour_batches=np.zeros(64 * words + 1, np.int64),
        colour_cursor=np.zeros(64 * words, np.int64),
        order=np.zeros(n_contacts, np.int64),
        colour_key=np.zeros((n_contacts, 5), np.int64),
        colour_key_n=np.full(1, -1, np.int64),
        colour_kept=np.zeros(1, bool),
        wide=aligned((batches * soft_step.STRIDE,)),
        lane_row=np.zeros(batches * 2 * soft_step.LANES, np.uint64),
        lane_slot=np.full(batches * soft_step.LANES, -1, np.int64),
        batch_kind=np.zeros(batches, np.uint8),
        batch_hard=np.zeros(batches, bool),
        batch_impact=np.zeros(batches, bool),
        batch_deep=np.zeros(batches, bool),
        row_mark=np.zeros(n + 1, bool),
        profile=old.profile if old is not None else np.zeros(D.N_STAGES, np.int64),
        steps_profiled=(old.steps_profiled if old is not None else np.zeros(1, np.int64)),
    )


def grown(need, counters, n, contacts, solver, awake_grid, resting_grid):
    """The buffers after growing those the kernel reported too small (``need``, the bits of
    counters[GROW_NEEDED]), each to twice what it needs, their contents carried over: returns
    (contacts, solver, awake_grid, resting_grid), the ones not grown as they were. ``n``: the
    number of dynamic bodies."""
    c = counters
    if need & D.GROW_CONTACTS:
        old = contacts
        cap = 2 * len(old.awake)
        new = new_contacts(cap, n)
        k = int(c[D.N_SLOTS])
        for name in ("contact_int", "contact_float", "point_float", "point_id"):
            getattr(new, name)[:k] = getattr(old, name)[:k]
        new.head[:] = old.head
        new.degree[:] = old.degree
        na = int(c[D.N_AWAKE_CONTACTS])
        new.awake[:na] = old.awake[:na]
        contacts = new
    if need & (D.GROW_CONTACTS | D.GROW_SOLVER):
        solver = new_solver(n, len(contacts.awake), 2 * max(1, int(c[D.MAX_DEGREE])), solver)
    grids = [awake_grid, resting_grid]
    for k, bit in enumerate((D.GROW_AWAKE_GRID, D.GROW_RESTING_GRID)):
        if need & bit:
            info = grids[k].info
            grids[k] = grid_buffers(
                2 * int(info[D.NEEDED_ENTRIES]), 2 * int(info[D.NEEDED_BUCKETS])
            )
    return contacts, solver, grids[0], grids[1]
