"""Geometry shared by the experiments that measure overlap themselves, with one routine for every
system (fig_tradeoff, table_extremes): padding polygons to one vertex count, world vertices of a
body, and the separating-axis separation of many polygon pairs at once (numpy, not the solver)."""

import numpy as np

from sim import geometry


def pad(v, k):
    """(k,2): polygon ``v`` (K,2) padded to k vertices by repeating its last vertex (a repeated
    vertex adds a zero-length edge, which ``separation`` skips)."""
    return np.concatenate([v, np.repeat(v[-1:], k - len(v), axis=0)])


def world_vertices(body):
    """(K,2) m: a sim.Body's vertices placed at its position and angle."""
    return geometry.place(body.vertices, body.position, body.angle)


def separation(a, b):
    """(P,) m: for each pair, the largest separation of polygon b from polygon a along a's outward
    edge normals (negative: every edge of a has some vertex of b behind it). a, b: (P,K,2) CCW.
    Two convex polygons overlap by minus the larger of separation(a, b) and separation(b, a)."""
    edge = np.roll(a, -1, axis=1) - a  # (P,K,2)
    length = np.hypot(edge[..., 0], edge[..., 1])
    safe = np.where(length, length, 1.0)[..., None]
    normal = np.stack([edge[..., 1], -edge[..., 0]], axis=-1) / safe
    # (P,K_edges,K_vertices): signed distance of b's vertices from a's edge lines
    dist = np.einsum("pec,pvc->pev", normal, b) - np.einsum("pec,pec->pe", normal, a)[..., None]
    sep = dist.min(axis=2)
    sep[length < 1e-12] = -np.inf  # padded, zero-length edges
    return sep.max(axis=1)
