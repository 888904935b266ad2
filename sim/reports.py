"""What a ``sim.World`` reports about its solver, read-only: the contact points of the last step
(``contact_points``, behind ``World.contacts()``) and the bookkeeping snapshot behind
``World.inspect()`` (``Inspection``).

Split from ``world.py`` by job: the World builds and steps; these only read the arrays the step
loop left, and copy what they hand out, so that nothing a caller does with a report reaches the
run. Each takes the arrays it reads, not the World, so that no private state crosses modules.
"""

import numpy as np

from . import data as D
from . import soft_step


def contact_points(contacts, counters, position):
    """Every point of this step's active contacts (``World.contacts()`` says what each array
    holds): copies, from the contact store ``contacts``, the ``counters`` and the bodies'
    positions ``position`` (anchors are stored relative to body B's centre)."""
    c = contacts
    rows, cols = _point_rows(contacts, counters)
    b = c.contact_int[rows, D.BODY_B]
    # field by field: gathering whole point rows first copied every column of every point (0.3
    # GB at 10^6 boxes) to hand out a few
    pf = c.point_float
    return {
        "body_a": c.contact_int[rows, D.BODY_A],
        "body_b": b,
        "point": pf[rows[:, None], cols[:, None], [D.ANCHOR_BX, D.ANCHOR_BY]] + position[b],
        "normal": c.contact_float[rows[:, None], [D.NORMAL_X, D.NORMAL_Y]],
        "separation": pf[rows, cols, D.SEPARATION],
        "end_separation": pf[rows, cols, D.END_SEPARATION],
        "slop": c.contact_float[rows, D.SLOP],
        "normal_impulse": pf[rows, cols, D.NORMAL_IMPULSE],
        "tangent_impulse": pf[rows, cols, D.TANGENT_IMPULSE],
    }


def deepest_point(contacts, counters):
    """(separation m, body_a, body_b) of the deepest point of this step's active contacts, or None
    if there is none: what the World's overlap check reads, without building the whole report
    (at 10^6 boxes the report took ~1 s of the World's set-up)."""
    rows, cols = _point_rows(contacts, counters)
    if not len(rows):
        return None
    separation = contacts.point_float[rows, cols, D.SEPARATION]
    k = int(np.argmin(separation))
    ci = contacts.contact_int
    return float(separation[k]), int(ci[rows[k], D.BODY_A]), int(ci[rows[k], D.BODY_B])


def _point_rows(contacts, counters):
    """(contact slot, point index) of every point of this step's active contacts, in order."""
    slots = contacts.active[: int(counters[D.N_ACTIVE])]
    n_pts = contacts.contact_int[slots, D.POINT_COUNT]
    rows = np.repeat(slots, n_pts)
    # each point's index within its contact: its place in the list less where its contact's
    # points begin (one array operation: a Python loop over the contacts took 0.7 s of a World's
    # set-up at 10^6 boxes)
    first = np.cumsum(n_pts) - n_pts
    return rows, np.arange(len(rows)) - np.repeat(first, n_pts)


def pair_colours(solver, contact_int, n_colours):
    """{(body_a, body_b): colour} of the contacts in the solver's batches, in the order the
    sweeps solve them."""
    out = {}
    for colour in range(n_colours):
        lanes = solver.lane_slot[
            solver.colour_batches[colour] * soft_step.LANES : solver.colour_batches[colour + 1]
            * soft_step.LANES
        ]
        for slot in lanes[lanes >= 0]:
            out[(int(contact_int[slot, D.BODY_A]), int(contact_int[slot, D.BODY_B]))] = colour
    return out


class Inspection:
    """What a World's solver holds after its last step, as plain copies (changing them changes
    nothing in the World).

      contacts             the active contacts' points (``World.contacts()``)
      n_contacts           live contact slots: pairs whose fat boxes overlap
      n_awake_contacts     of those, the ones with an awake body (looked at every step)
      n_active             of those, the ones with points this step (solved)
      n_refreshed          of the awake ones, refreshed from their stored points last step
      n_skipped            of the awake ones, skipped last step: apart by more than they could
                           close (``narrowphase.update_manifolds``)
      awake                (n_awake,) indices of the awake bodies
      solver_inv_mass      (N,) 1/kg the solver used (0 for frozen and held bodies)
      n_colours, n_batches the last step's constraint colours and batches of ``LANES``
      pair_colour          {(body_a, body_b): colour} of the last step's active contacts, in the
                           order the sweeps solve them (body_a = -1: the floor)
      lanes                soft_step.LANES
      batch_fill           fraction of the batch lanes that hold a contact
      batch_kinds          (n_batches,) soft_step layout.MOVABLE or FIXED_A of each batch (FIXED_A:
                           body A of every lane cannot move, and the sweeps leave its terms out)
      resting_rebuilds     how many times the resting grid was rebuilt since the start
      presolve_sweeps      sweeps the initial-impulse solve took
      presolve_converged   whether it stopped on its tolerance (False: on its sweep cap, or none)
      regrown              how many times a buffer the step loop outgrew was grown
      sweeps, impacts      fast bodies swept (stage ``continuous``), and cut back to an impact
      toi_pairs            pairs the sweeps measured at their end poses (a time-of-impact
                           evaluation each; a pair surely apart is not measured: ``sim.sweep``)
      n_hard_batches       batches that got soft_step.HARD_SWEEPS extra relax sweeps (they hold a
                           contact touching a body in a contact of mass ratio > HARD_RATIO)
      n_impact_batches     batches that got ``impact_iterations`` extra biased sweeps in the last
                           step (they touch a body in a contact approaching faster than
                           soft_step.IMPACT_SWEEP_SPEED)
      n_deep_batches       batches that got soft_step.DEEP_SWEEPS extra biased sweeps in the last
                           step (they touch a body in a contact deeper than DEEP_SLOPS slops)
      certificates         rest certificates tried since the start (extended:
                           ``sim.freeze.certificate``; one per candidate body per step)
      quiet_steps          steps skipped since the start by the "quiet" fast path: nothing was
                           awake, and a step since had begun and ended so (``kernel.run``)

    Built by ``World.inspect()`` from the World's arrays: ``points`` its contact points,
    ``counters``, ``activity``, ``solver`` and ``contacts`` the step loop's state, ``n_bodies``
    the dynamic bodies, ``regrown`` the World's count of grown buffers.
    """

    def __init__(self, points, counters, activity, solver, contacts, n_bodies, regrown):
        c = counters
        self.contacts = points
        self.n_contacts = int(c[D.N_LIVE])
        self.n_awake_contacts = int(c[D.N_AWAKE_CONTACTS])
        self.n_active = int(c[D.N_ACTIVE])
        self.n_refreshed = int(c[D.N_REFRESHED])
        self.n_skipped = int(c[D.N_SKIPPED])
        self.awake = activity.awake[: int(c[D.N_AWAKE])].copy()
        self.solver_inv_mass = activity.solver_inv_mass[:n_bodies].copy()
        self.n_colours = int(c[D.N_COLOURS])
        self.n_batches = int(c[D.N_BATCHES])
        self.pair_colour = pair_colours(solver, contacts.contact_int, self.n_colours)
        self.lanes = soft_step.LANES
        self.batch_fill = self.n_active / (self.n_batches * self.lanes) if self.n_batches else 1.0
        self.batch_kinds = solver.batch_kind[: self.n_batches].copy()
        self.resting_rebuilds = int(c[D.N_REBUILDS])
        self.presolve_sweeps = int(c[D.PRESOLVE_SWEEPS])
        self.presolve_converged = bool(c[D.PRESOLVE_CONVERGED])
        self.regrown = regrown
        self.sweeps = int(c[D.N_SWEPT])
        self.impacts = int(c[D.N_IMPACTS])
        self.toi_pairs = int(c[D.N_TOI_PAIRS])
        self.n_hard_batches = int(c[D.N_HARD])
        self.n_impact_batches = int(c[D.N_IMPACT_BATCHES])
        self.n_deep_batches = int(c[D.N_DEEP_BATCHES])
        self.certificates = int(c[D.N_CERTIFICATES])
        self.quiet_steps = int(c[D.N_QUIET])

    def __repr__(self):
        return (
            f"Inspection(contacts={self.n_contacts}, awake_contacts={self.n_awake_contacts}, "
            f"active={self.n_active}, colours={self.n_colours}, batches={self.n_batches})"
        )
