"""Colouring: the active contacts are split into colours, no two contacts of one colour sharing a
body the solver moves, and each colour is cut into batches of LANES (``colour``); the buffers
this needs are sized by ``capacity`` and ``mask_words``."""

from numba.cpython.unsafe.numbers import trailing_zeros

from ..data import BODY_A, BODY_B, N_ACTIVE, N_AWAKE, N_BATCHES, N_COLOURS
from ..jit import inline_kernel, lean_kernel
from .bodies import row_of
from .layout import LANES, U64
from .parameters import HARD_RATIO


@inline_kernel
def max_colours(max_degree):
    """Colours ``colour`` may use when no body has more than ``max_degree`` contacts: greedy
    colouring of the contacts between movable bodies uses at most 2 max_degree - 1, and the
    contacts with an immovable body, coloured after those, at most max_degree more."""
    return 3 * max(1, max_degree)


def capacity(n_contacts, max_degree):
    """Batches the solver may need for ``n_contacts`` contacts when no body has more than
    ``max_degree``: every colour may end in one part-filled batch."""
    return -(-n_contacts // LANES) + max_colours(max_degree) + 1


def mask_words(max_degree):
    """uint64 words of colour bits per body row."""
    return max(1, -(-max_colours(max_degree) // 64))


@inline_kernel
def _movable(i, n_dynamic, activity):
    """Does the solver change body i's velocity (so two contacts on it must not share a batch)?"""
    return (
        0 <= i < n_dynamic
        and activity.awake_slot[i] >= 0
        and (activity.solver_inv_mass[i] > 0.0 or activity.solver_inv_inertia[i] > 0.0)
    )


@inline_kernel
def _solver_row(i, n_dynamic, activity):
    """Body i's solver row if the solver moves it, else the dummy row 0."""
    return row_of(i, n_dynamic, activity.awake_slot) if _movable(i, n_dynamic, activity) else 0


@inline_kernel
def _first_free_colour(masks, ra, rb, lowest, n_words):
    """The first colour >= ``lowest`` used by neither row (row 0, immovable, uses none), marked
    used at both; -1 if none is free."""
    for q in range(lowest // 64, n_words):
        used = U64(0)
        if ra > 0:
            used |= masks[ra, q]
        if rb > 0:
            used |= masks[rb, q]
        if q == lowest // 64:
            used |= (U64(1) << U64(lowest % 64)) - U64(1)  # the colours below ``lowest``
        free = ~used
        if free != U64(0):
            bit = trailing_zeros(free)
            one = U64(1) << U64(bit)
            if ra > 0:
                masks[ra, q] |= one
            if rb > 0:
                masks[rb, q] |= one
            return q * 64 + bit
    return -1


@inline_kernel
def _mark_hard_rows(n_active, n_dynamic, contacts, activity, solver):
    """Mark (solver.row_mark) the rows of both bodies of every active contact whose movable
    bodies' masses differ by more than HARD_RATIO; returns whether any was."""
    ci = contacts.contact_int
    inv_mass = activity.solver_inv_mass
    found = False
    for k in range(n_active):
        s = contacts.active[k]
        ra = _solver_row(ci[s, BODY_A], n_dynamic, activity)
        rb = _solver_row(ci[s, BODY_B], n_dynamic, activity)
        if ra > 0 and rb > 0:
            ma = inv_mass[ci[s, BODY_A]]
            mb = inv_mass[ci[s, BODY_B]]
            if ma > HARD_RATIO * mb or mb > HARD_RATIO * ma:
                solver.row_mark[ra] = True
                solver.row_mark[rb] = True
                found = True
    return found


@inline_kernel
def _same_as_last(n_active, n_dyn, contacts, activity, solver):
    """Is the colouring problem the one coloured last: the same active contacts (slots, and the
    bodies in them: a slot freed and taken by another pair in one step keeps its number), in the
    same order, between the same solver rows? Records this one either way."""
    ci = contacts.contact_int
    key = solver.colour_key
    same = n_active == solver.colour_key_n[0]
    for k in range(n_active):
        s = contacts.active[k]
        a = ci[s, BODY_A]
        b = ci[s, BODY_B]
        ra = _solver_row(a, n_dyn, activity)
        rb = _solver_row(b, n_dyn, activity)
        if same and (
            key[k, 0] != s or key[k, 1] != a or key[k, 2] != b or key[k, 3] != ra or key[k, 4] != rb
        ):
            same = False
        key[k, 0] = s
        key[k, 1] = a
        key[k, 2] = b
        key[k, 3] = ra
        key[k, 4] = rb
    solver.colour_key_n[0] = n_active
    return same


@lean_kernel
def colour(settings, counters, contacts, activity, solver):
    """Colour the active contacts greedily (first colour free at both movable bodies; those with
    an immovable body in colours after all the others, see below) and lay them out: colour c's
    contacts fill batches colour_batches[c] .. colour_batches[c+1]-1, in active order (those
    touching a body in a hard contact first), the last batch padded with empty lanes (slot -1).
    Returns the number of batches.

    The colouring depends only on the active contacts' slots and solver rows, in order (and, where
    ``settings.mixed_masses``, on the bodies' masses through the hard contacts: such Worlds always
    colour afresh). When those are the step before's, as in a resting stack, the step before's
    colouring and layout still stand (nothing else writes them) and are kept: the same result
    without the greedy search. The stage took 0.018-0.020 ms a step on pyramid(40) and 0.005
    with this; rest_row(5000) 0.050 and 0.017 (``World.profile``, interleaved). Box2D v3 keeps its
    constraint colours from step to step too. ``solver.colour_kept`` tells ``prepare``, which then
    leaves what depends on the pair only (masses, materials, softness) where it is (prepare:
    pyramid(40) 0.048 -> 0.041 ms, rest_row(5000) 0.19-0.21 -> 0.18)."""
    n_dyn = settings.n_dynamic
    n_active = counters[N_ACTIVE]
    kept = _same_as_last(n_active, n_dyn, contacts, activity, solver) and not settings.mixed_masses
    solver.colour_kept[0] = kept
    if kept:
        return counters[N_BATCHES]
    ci = contacts.contact_int
    masks = solver.colour_mask
    n_words = masks.shape[1]
    n_awake = counters[N_AWAKE]
    for r in range(n_awake + 1):
        for q in range(n_words):
            masks[r, q] = U64(0)
    counts = solver.colour_batches  # first used as per-colour counts
    n_colours_max = counts.shape[0] - 1
    for c in range(n_colours_max + 1):
        counts[c] = 0
    order = solver.order  # colour of each active contact (~colour: hard), for now
    # Contacts touching a body in a hard contact (HARD_RATIO) get extra relax sweeps, by batch:
    # laid out first in their colour, they fill few batches instead of tainting most (a pile of
    # random polygons, masses 0.005-0.39 kg: 41 of 51 batches were hard with them spread out).
    any_hard = settings.mixed_masses and _mark_hard_rows(
        n_active, n_dyn, contacts, activity, solver
    )
    # Contacts between two movable bodies first, then those with an immovable one (static, frozen,
    # the floor) in colours after all of theirs: within a sweep the support is solved last, so the
    # sweep ends with every body pushed out of what cannot move, as in Box2D v3, which gives static
    # contacts the highest colours. Solved first, a support is undone by every contact above it
    # in the same sweep: a 0.5 m box landing at 26 m/s on one resting on the floor drove it 14 cm
    # into the floor.
    n_colours = 0
    for immovable in range(2):
        lowest = n_colours if immovable == 1 else 0
        for k in range(n_active):
            s = contacts.active[k]
            ra = _solver_row(ci[s, BODY_A], n_dyn, activity)
            rb = _solver_row(ci[s, BODY_B], n_dyn, activity)
            if (ra == 0 or rb == 0) != (immovable == 1):
                continue
            c = _first_free_colour(masks, ra, rb, lowest, n_words)
            # max_colours() guarantees one: each body has at most max_degree contacts
            hard = any_hard and (
                (ra > 0 and solver.row_mark[ra]) or (rb > 0 and solver.row_mark[rb])
            )
            order[k] = ~c if hard else c
            counts[c] += 1
            n_colours = max(n_colours, c + 1)
    # counts -> first batch of each colour
    batch = 0
    for c in range(n_colours):
        n = counts[c]
        counts[c] = batch
        batch += (n + LANES - 1) // LANES
    counts[n_colours] = batch
    n_batches = batch
    for e in range(n_batches * LANES):
        solver.lane_slot[e] = -1
    cursor = solver.colour_cursor  # next free lane of each colour
    for c in range(n_colours):
        cursor[c] = counts[c] * LANES
    for first_pass in range(2 if any_hard else 1):  # hard contacts first, then the rest
        for k in range(n_active):
            c = order[k]
            if any_hard and (c < 0) != (first_pass == 0):
                continue
            if c < 0:
                c = ~c
            solver.lane_slot[cursor[c]] = contacts.active[k]
            cursor[c] += 1
    if any_hard:
        for r in range(n_awake + 1):
            solver.row_mark[r] = False
    counters[N_BATCHES] = n_batches
    counters[N_COLOURS] = n_colours
    return n_batches
