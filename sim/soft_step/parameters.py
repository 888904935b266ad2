"""The soft contact's parameters: defaults (each with the measurement that chose it) and the
stiffness of a contact pair (``pair_hertz``) turned into the soft constraint's coefficients
(``softness``, Catto's soft step)."""

import numpy as np

from ..jit import inline_kernel

#: Default soft-contact parameters. The damping ratio is three times Box2D's 10: with contacts that
#: carry their load (see LOAD_TIME), a 50-box column started without any initial solve oscillated
#: and buckled at 10 and settles at 30 (measured when the soft step was tuned). push_speed is
#: Box2D's.
DAMPING_RATIO = 30.0
PUSH_SPEED = 3.0
#: Stiffness caps as fractions of the substep rate: hertz * h. A contact stiffer than 1/8 of the
#: substep rate (Box2D's cap) made a 20-high pyramid jitter and grow a rocking mode; against an
#: immovable body twice that. The default stiffness is the cap itself ("as stiff as the substep
#: allows": 30 Hz at 4 substeps of 1/60 s, Box2D's default), so more substeps give stiffer
#: contacts.
DYNAMIC_CAP = 0.125
STATIC_CAP = 0.25
#: A contact must be stiff relative to gravity at the size of its bodies, omega^2 >= STIFFNESS_RATIO
#: g / size, or a small body rocks on it (a column of 1 mm boxes fell over at a ratio of 4, rocked
#: slowly at 15 and stood at 36 and above). Small bodies get stiffer contacts up to the cap; a body
#: too small even at the cap is refused (``tolerances.check_step``).
STIFFNESS_RATIO = 25.0
#: Time constant (s) with which a contact's carried load follows the impulse it applies. A soft
#: contact is a spring: it carries a load L by sinking L / (m omega^2), and in a stack every contact
#: sinks by what it carries (a 10-box column sank 3 cm, a 50-box one 0.7 m). Here the spring only
#: acts on the *change* of load: the load the contact has carried for a while is held rigidly
#: (``_normal_rows``: the leak is impulse_scale * (impulse - carried)), so a resting stack does not
#: sink at all. Followed instantly the carried load becomes an integrator that makes tall columns
#: oscillate; followed over a third of a second, the spring damps first. Faster is not better
#: overall (measured on 2503cec; drop(30) seeds 0-19, 20 s, sim-off): at 0.05 s piles settle sooner
#: (a body moving at 1 mm/s or more until step 270 instead of 464, median; 19 of 20 at rest over
#: their 20th second instead of 17; extended froze them whole in 182 steps instead of 224) and a box
#: sliding to a stop no longer crept (2e-8 m/s instead of 2.4e-6; now stopped by carrying the split
#: of a two-point manifold on an immovable body at once, see packing's store), but pyramid(40) moved
#: 0.47 m in 5 s instead of 2.6 mm, a 50-box column started without the presolve fell (0.88 m; 0.47
#: m at 0.15 s, 0.24 m at 0.1 s) and a 1000:1 stack toppled. Releasing load fast and taking it up
#: slowly (0.05 s and 1/3 s, 1/3 s both ways near a mass ratio) kept the stacks standing but gave
#: the piles nothing beyond chaos (1 mm/s until step 493, extended 218 steps against sleep's 184).
LOAD_TIME = 1.0 / 3.0
#: A two-point manifold is solved as one 2x2 block unless K's condition number is worse than this
#: (the points nearly coincide, or stand close under a long arm: a plank on its end): then as one
#: point alone, or, where neither alone holds, as one row shared by both (``two_row_impulses``).
MAX_CONDITION = 1000.0
#: A contact between movable bodies whose masses differ more than this is "hard": Gauss-Seidel
#: converges on it at ~M/(M+m) per sweep (a heavy box on a light one sinks into it while the
#: light one is pushed into the floor). HARD_SWEEPS more relax sweeps per substep go to the batches
#: that touch a body in such a contact, and only to them: a 1000:1 stack dropped onto the floor
#: toppled with one relax sweep and stands with three (final overlap 4 mm), at no cost to scenes
#: without mass ratios.
HARD_RATIO = 10.0
HARD_SWEEPS = 2
#: m/s: a contact point that approached faster than this at the start of a step was an impact,
#: and its impulse is not warm-started into the next step (see ``store``). With the restitution
#: threshold (1 m/s) instead, a settling pile of 30 polygons kept 1.7 cm of overlap (under 1 cm with
#: every point warm-started): ordinary landings need their warm start.
IMPACT_SPEED = 10.0
#: Impacts. A landing is a large velocity jump through a chain of contacts (a box onto the boxes
#: below, they onto the floor), and one Gauss-Seidel sweep per substep leaves much of it
#: unconverged: the bodies' velocities then disagree with their contacts, and the positions are
#: integrated with them, before the relax sweep (the only one with friction rows) sees them. The
#: error is a sideways slide that never comes back: on fig_tradeoff's landing scene (24 unit boxes
#: landing flat at 3-5 m/s, the exact answer moves none sideways) boxes ended up to 32.6 mm from
#: their rest pose. So in a step where a contact point approaches faster than IMPACT_SWEEP_SPEED
#: (at the start of the step), every batch touching one of the point's bodies gets
#: ``impact_iterations`` (World; default IMPACT_ITERATIONS) more biased sweeps per substep, with
#: friction rows. Measured on that scene (max distance from the rest pose): 0 extra sweeps 32.6
#: mm, 2: 10.4, 4: 4.2, 8: 0.69, 16: 0.44 (pybullet at its 50 iterations: 1.05 mm). Needed, each
#: measured at 8: friction in them (without: 2.7 mm), the batches around the impact bodies and
#: not only those holding the impact contacts (24.7 mm), and every substep of the step (only the
#: first: 41 mm). Extra *relax* sweeps there made it worse (4 more: 23 mm). Hard batches
#: (HARD_RATIO) get none: converged soft rows carry a heavy body's load on a spring sized for the
#: light body's mass (a dropped 100:1 stack, falling asleep, kept 11.5 mm of overlap instead of
#: 6.5). A step without an impact pays one test per lane.
IMPACT_SWEEP_SPEED = 1.0  # m/s
IMPACT_ITERATIONS = 8
#: Deep contacts. A contact pushed far into its partner (by a landing, by a load shifting in a
#: pile) is opened by the soft bias of one sweep per substep, and a sweep converges through
#: the bodies resting on it only slowly: in a settling pile of 30 polygons a 44 g body stayed
#: 6 mm inside a heavier one for seconds, opening at 1.5 mm/s where the bias alone asks for
#: 18 mm/s. So a batch touching a body with a contact point deeper than DEEP_SLOPS times its
#: pair's slop at the start of a step gets DEEP_SWEEPS more biased sweeps per substep, with
#: friction rows (the impact sweeps' kernel), hard batches left out (as there). Measured on
#: drop(30) seeds 0-19 (20 s, sim-off): a body still moving at 1 mm/s or more until step 398
#: instead of 464.5 (median), at 2 cm/s until 160 instead of 175.5, and all 20 piles at rest over
#: their 20th second instead of 17; the landing (fig_tradeoff), the dropped 100:1 and 1000:1
#: stacks and placed pyramids are unchanged. Cost: drop(200) 110 -> 116 us a step. With 8 sweeps
#: (the impact sweeps' count) it cost 29% there.
DEEP_SLOPS = 2.0
DEEP_SWEEPS = 2
#: Restitution sweeps after the substeps (see ``restitution``).
RESTITUTION_SWEEPS = 4


@inline_kernel
def softness(hertz, zeta, h):
    """(bias_rate 1/s, mass_scale, impulse_scale) of a soft constraint (Catto)."""
    if hertz <= 0.0:
        return 0.0, 1.0, 0.0
    omega = 2.0 * np.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@inline_kernel
def pair_hertz(base_hertz, size, gravity, h, immovable):
    """Hz: the stiffness of a contact whose bodies' smaller size is ``size`` m, at substep h s.

    ``base_hertz`` (the World's contact_hertz; 0 = the cap), raised for small bodies so that
    omega^2 >= STIFFNESS_RATIO g / size, doubled against an immovable body (so a pile does not sink
    into its support), and capped at DYNAMIC_CAP (STATIC_CAP) of the substep rate."""
    cap = (STATIC_CAP if immovable else DYNAMIC_CAP) / h
    hertz = base_hertz if base_hertz > 0.0 else DYNAMIC_CAP / h
    if gravity > 0.0 and size > 0.0:
        hertz = max(hertz, np.sqrt(STIFFNESS_RATIO * gravity / size) / (2.0 * np.pi))
    if immovable:
        hertz *= 2.0
    return min(hertz, cap)
