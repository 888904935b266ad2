"""The persistent contact store: its slots, the per-body lists through them, and the awake list.

A contact slot is made when two bodies' fat boxes start to overlap (``broadphase``) and freed when
they stop: in between, every step either body is awake, its manifold (0-2 points) is recomputed
from the current poses, and impulses carry over from the last step's points with the same feature
id (warm starting): that is the narrowphase, ``sim.narrowphase``, kept apart because it only
fills the slots this module keeps (Box2D v3 likewise keeps its manifold functions apart from its
contact bookkeeping). Nothing is allocated in the step loop: slots come from a free list, and a
full store makes the step return GROW before anything has changed (the World grows it and
retries).

Which contacts are looked at is data, not a test in every loop (as sleeping is in Box2D v3):
``contacts.awake`` lists the slots with at least one awake body. Freezing a body moves its contacts
whose other body cannot move out of that list (``sleep_contacts_of``), waking moves them back
(``wake_contacts_of``); each dynamic body's contacts form a doubly linked list through the slots,
so both cost the body's own contact count. Contacts between resting bodies cost nothing.

Columns are named in ``sim.data`` (BODY_A, NORMAL_X, NORMAL_IMPULSE...). A pair (a, b) has a < b;
a = -1 is the floor; the normal points from A to B.
"""

from .data import (
    ALIVE,
    AWAKE_INDEX,
    AWAKE_UNSORTED,
    BODY_A,
    BODY_B,
    FREE_HEAD,
    GROW_CONTACTS,
    GROW_NEEDED,
    INCIDENT,
    MAX_DEGREE,
    NEXT_A,
    NEXT_B,
    N_AWAKE_CONTACTS,
    N_LIVE,
    N_SLOTS,
    POINT_COUNT,
    PREV_A,
    PREV_B,
    REFERENCE,
    SLOP,
    SPECULATIVE,
)
from .jit import inline_kernel, kernel, lean_kernel


# ---- the per-body lists -------------------------------------------------------------------------
@inline_kernel
def _next_of(i, s, contact_int):
    """The slot after s in body i's list."""
    return contact_int[s, NEXT_A] if contact_int[s, BODY_A] == i else contact_int[s, NEXT_B]


@inline_kernel
def _set_link(i, s, column_a, column_b, value, contact_int):
    """Set s's NEXT or PREV field on body i's side (column_a when i is BODY_A, else column_b)."""
    if contact_int[s, BODY_A] == i:
        contact_int[s, column_a] = value
    else:
        contact_int[s, column_b] = value


@inline_kernel
def _link(i, s, contacts):
    """Put slot s at the head of dynamic body i's list."""
    ci = contacts.contact_int
    h = contacts.head[i]
    _set_link(i, s, NEXT_A, NEXT_B, h, ci)
    _set_link(i, s, PREV_A, PREV_B, -1, ci)
    if h >= 0:
        _set_link(i, h, PREV_A, PREV_B, s, ci)
    contacts.head[i] = s
    contacts.degree[i] += 1


@inline_kernel
def _unlink(i, s, contacts):
    ci = contacts.contact_int
    if ci[s, BODY_A] == i:
        nxt = ci[s, NEXT_A]
        prv = ci[s, PREV_A]
    else:
        nxt = ci[s, NEXT_B]
        prv = ci[s, PREV_B]
    if prv >= 0:
        _set_link(i, prv, NEXT_A, NEXT_B, nxt, ci)
    else:
        contacts.head[i] = nxt
    if nxt >= 0:
        _set_link(i, nxt, PREV_A, PREV_B, prv, ci)
    contacts.degree[i] -= 1


@inline_kernel
def find(a, b, n_dynamic, contacts):
    """The slot of pair (a, b) (a < b, a = -1 the floor), or -1: a walk of the shorter list."""
    ci = contacts.contact_int
    i = b
    if 0 <= a < n_dynamic and (b >= n_dynamic or contacts.degree[a] < contacts.degree[b]):
        i = a
    if i >= n_dynamic:
        return -1
    s = contacts.head[i]
    while s >= 0:
        if ci[s, BODY_A] == a and ci[s, BODY_B] == b:
            return s
        s = _next_of(i, s, ci)
    return -1


# ---- the awake list -----------------------------------------------------------------------------
@inline_kernel
def _add_awake(s, contacts, counters):
    ci = contacts.contact_int
    if ci[s, AWAKE_INDEX] >= 0:
        return
    k = counters[N_AWAKE_CONTACTS]
    contacts.awake[k] = s
    ci[s, AWAKE_INDEX] = k
    counters[N_AWAKE_CONTACTS] = k + 1
    counters[AWAKE_UNSORTED] += 1


@inline_kernel
def _remove_awake(s, contacts, counters):
    """Swap-remove slot s from the awake list."""
    ci = contacts.contact_int
    k = ci[s, AWAKE_INDEX]
    if k < 0:
        return
    last = counters[N_AWAKE_CONTACTS] - 1
    moved = contacts.awake[last]
    contacts.awake[k] = moved
    ci[moved, AWAKE_INDEX] = k
    ci[s, AWAKE_INDEX] = -1
    counters[N_AWAKE_CONTACTS] = last
    if k != last:
        counters[AWAKE_UNSORTED] += 1


@inline_kernel
def _is_awake(i, n_dynamic, awake_slot):
    return 0 <= i < n_dynamic and awake_slot[i] >= 0


@inline_kernel
def wake_contacts_of(i, contacts, counters):
    """Body i has woken: every contact of its list is awake now."""
    ci = contacts.contact_int
    s = contacts.head[i]
    while s >= 0:
        _add_awake(s, contacts, counters)
        s = _next_of(i, s, ci)


@inline_kernel
def sleep_contacts_of(i, n_dynamic, awake_slot, contacts, counters):
    """Body i has frozen: its contacts whose other body cannot move either leave the awake list
    (with their manifold and impulses kept, to warm start the pair if it wakes)."""
    ci = contacts.contact_int
    s = contacts.head[i]
    while s >= 0:
        other = ci[s, BODY_A] if ci[s, BODY_B] == i else ci[s, BODY_B]
        if not _is_awake(other, n_dynamic, awake_slot):
            _remove_awake(s, contacts, counters)
        s = _next_of(i, s, ci)


@inline_kernel
def _key(s, contact_int, stride):
    """The pair's order: floor pairs first, then by the lower body, then the higher."""
    return (contact_int[s, BODY_A] + 1) * stride + contact_int[s, BODY_B]


#: key * capacity + slot must stay below this (int64): a key is below stride^2
_PACKED_LIMIT = 2.0**62


@inline_kernel
def _swap(keys, slots, i, j):
    keys[i], keys[j] = keys[j], keys[i]
    slots[i], slots[j] = slots[j], slots[i]


@inline_kernel
def _sift_down(keys, slots, root, end):
    """Restore the max-heap below ``root`` within keys[:end] (slots moved alongside)."""
    while True:
        child = 2 * root + 1
        if child >= end:
            return
        if child + 1 < end and keys[child + 1] > keys[child]:
            child += 1
        if keys[root] >= keys[child]:
            return
        _swap(keys, slots, root, child)
        root = child


@inline_kernel
def merge_nearly_sorted(keys, spare, n):
    """Sort keys[:n] (distinct int64) in place, in O(n + m log m) for m keys out of order;
    spare[:n] is overwritten. The awake list is the last sort's order with a few changes: new
    contacts appended at its end, and removed ones replaced by its last entry (``_remove_awake``).
    So the keys that keep the order (each above the last one kept and below the next one) stay
    where they are, in order; the others (new, or moved by a removal) go to ``spare``, are sorted
    there, and the two runs are merged from the back. (A full sort of drop(200)'s ~800 awake
    contacts took 9-14 us a step while the pile landed, 33 new contacts a step.)"""
    kept = 0
    out = 0
    for k in range(n):
        key = keys[k]
        if (kept == 0 or key > keys[kept - 1]) and (k + 1 == n or key < keys[k + 1]):
            keys[kept] = key  # (kept <= k: nothing unread is overwritten)
            kept += 1
        else:
            spare[out] = key
            out += 1
    if out == 0:
        return
    spare[:out].sort()
    i = kept - 1
    j = out - 1
    for w in range(n - 1, -1, -1):  # w >= i always: the write never passes the read
        if j < 0:
            break
        if i >= 0 and keys[i] > spare[j]:
            keys[w] = keys[i]
            i -= 1
        else:
            keys[w] = spare[j]
            j -= 1


@kernel
def sort_awake(n_bodies, contacts, counters):
    """Put the awake contacts back in pair order, if any was added or removed since the last sort.

    The solver's result depends on the order it meets contacts in (Gauss-Seidel, colouring), and
    that order must not depend on history: a stack frozen and woken by an impact must be solved
    exactly as the same stack that never froze, or a freezing policy would differ from ``off`` by
    solver noise, not by freezing. A few new contacts go in by insertion; many (a new World, a
    large wake, a landing) by a sort in place."""
    if counters[AWAKE_UNSORTED] == 0:
        return
    ci = contacts.contact_int
    awake = contacts.awake
    n = counters[N_AWAKE_CONTACTS]
    stride = n_bodies + 1
    if counters[AWAKE_UNSORTED] > 32:
        # In place, in arrays the store already has: np.argsort and a copy made three new
        # arrays whenever a landing added many contacts (no array is allocated in the step
        # loop now). The keys go into ``active``, which update_manifolds, the one thing every
        # caller runs next, rebuilds from scratch; each pair's key is unique, so any correct
        # sort gives the one order.
        keys = contacts.active
        capacity = len(awake)
        if float(stride) * float(stride) * float(capacity) < _PACKED_LIMIT:  # (floats: no wrap)
            # each key with its slot in one int64 (key * capacity + slot), sorted as plain
            # integers: three times as fast as the heapsort below
            for k in range(n):
                keys[k] = _key(awake[k], ci, stride) * capacity + awake[k]
            merge_nearly_sorted(keys, awake, n)
            for k in range(n):
                awake[k] = keys[k] % capacity
        else:  # beyond int64 (~10^6 bodies): keys and slots side by side
            for k in range(n):
                keys[k] = _key(awake[k], ci, stride)
            for root in range(n // 2 - 1, -1, -1):
                _sift_down(keys, awake, root, n)
            for end in range(n - 1, 0, -1):
                _swap(keys, awake, 0, end)
                _sift_down(keys, awake, 0, end)
    else:
        for k in range(1, n):  # insertion sort: nearly sorted already
            s = awake[k]
            key = _key(s, ci, stride)
            j = k - 1
            while j >= 0 and _key(awake[j], ci, stride) > key:
                awake[j + 1] = awake[j]
                j -= 1
            awake[j + 1] = s
    for k in range(n):
        ci[awake[k], AWAKE_INDEX] = k
    counters[AWAKE_UNSORTED] = 0


# ---- making and freeing slots -------------------------------------------------------------------
@lean_kernel
def create(a, b, n_dynamic, slop, speculative, contacts, counters):
    """A new contact for pair (a, b), awake, with no points yet. Returns its slot, or -1 when the
    store is full (counters[GROW_NEEDED] says so; nothing was changed)."""
    ci = contacts.contact_int
    cf = contacts.contact_float
    s = counters[FREE_HEAD]
    if s >= 0:
        counters[FREE_HEAD] = ci[s, NEXT_A]
    elif counters[N_SLOTS] < ci.shape[0]:
        s = counters[N_SLOTS]
        counters[N_SLOTS] = s + 1
    else:
        counters[GROW_NEEDED] |= GROW_CONTACTS
        return -1
    ci[s, BODY_A] = a
    ci[s, BODY_B] = b
    ci[s, POINT_COUNT] = 0
    ci[s, REFERENCE] = -1
    ci[s, INCIDENT] = b
    ci[s, AWAKE_INDEX] = -1
    ci[s, ALIVE] = 1
    for j in range(2):
        contacts.point_id[s, j] = -1
        for col in range(contacts.point_float.shape[2]):
            contacts.point_float[s, j, col] = 0.0
    if a >= 0:
        cf[s, SLOP] = min(slop[a], slop[b])
        cf[s, SPECULATIVE] = min(speculative[a], speculative[b])
    else:
        cf[s, SLOP] = slop[b]
        cf[s, SPECULATIVE] = speculative[b]
    for i in (a, b):
        if 0 <= i < n_dynamic:
            _link(i, s, contacts)
            counters[MAX_DEGREE] = max(counters[MAX_DEGREE], contacts.degree[i])
    _add_awake(s, contacts, counters)
    counters[N_LIVE] += 1
    return s


@lean_kernel
def destroy(s, n_dynamic, contacts, counters):
    """Free slot s: out of both bodies' lists and the awake list, onto the free list."""
    ci = contacts.contact_int
    for i in (ci[s, BODY_A], ci[s, BODY_B]):
        if 0 <= i < n_dynamic:
            _unlink(i, s, contacts)
    _remove_awake(s, contacts, counters)
    ci[s, ALIVE] = 0
    ci[s, POINT_COUNT] = 0
    ci[s, NEXT_A] = counters[FREE_HEAD]
    counters[FREE_HEAD] = s
    counters[N_LIVE] -= 1
