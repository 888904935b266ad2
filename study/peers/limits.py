"""Limits the peer runners share.

A peer's step is C code: Ctrl-C cannot stop it, and its iteration count is a C int (pymunk raised
OverflowError from 2**31 on, pybullet the same). Far beyond any useful setting (Bullet's default is
10, Chipmunk's 10), and still a fraction of a second per step on a small scene."""

#: most solver iterations per step a peer runner accepts
MAX_ITERATIONS = 100_000
LIMITS_WHY = "a peer's step cannot be interrupted, and its iteration count is a C int"
