"""Peer engines running a ``sim.Scene`` with the same observables as ``sim.World``.

Every runner: ``Runner(scene, dt=..., iterations=..., sleeping=...)``, ``.step(n=1)``, and the
properties ``positions`` (N,2) m (centres of mass, row i = scene body i), ``angles`` (N,) rad,
``velocities`` (N,2) m/s, ``angular_velocities`` (N,) rad/s, ``asleep`` (N,) bool, ``name``,
``settings`` (dict, for results metadata), ``time`` s and ``step_count``.
"""
from .pymunk_runner import PymunkRunner

__all__ = ["PymunkRunner"]
