"""Freeze states of a body (docs/ARCHITECTURE.md §3). Stored as int8 in ``World.states``."""

from enum import IntEnum


class State(IntEnum):
    FREE = 0  # the seed's "vertical-unstable": moves freely, fully solved
    VERTICAL_STABLE = 1  # one vertex held on a floor: no vertical motion of that vertex
    ROTATION_STABLE = 2  # resting on two or more vertices: no rotation, no vertical motion
    SLEEPING = 3  # `sleep` policy: the island is asleep, the body is not solved
